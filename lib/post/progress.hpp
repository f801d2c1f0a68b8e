// SPDX-License-Identifier: MIT
// Progress reporting of the streamed post-processing passes: the library calls the sink after
// each frame; the pipeline decides when to print (wall-clock cadence) through its Log.
#pragma once

#include <cstddef>
#include <functional>

namespace pd::post {

/// Called with (product name, frames done, frames total) after each frame; may be empty.
using Progress = std::function<void(const char* what, std::size_t done, std::size_t total)>;

} // namespace pd::post
