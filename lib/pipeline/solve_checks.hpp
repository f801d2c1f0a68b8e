// SPDX-License-Identifier: MIT
// pd-solve's refusals before a run starts (internal to lib/pipeline/solve.cpp).
#pragma once

#include "pipeline/solve.hpp"

#include <string>

namespace pd::h5 {
class File;
}

namespace pd::pipeline {

/// Command-line values: finite, in range (CLI11 only parses them). InputError naming the option.
void check_options(const SolveOptions& opt);

/// A fresh run deletes the frames, observables and checkpoints of a file: only with --overwrite.
void refuse_existing_results(const h5::File& rf, const std::string& file);

} // namespace pd::pipeline
