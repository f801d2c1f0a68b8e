// SPDX-License-Identifier: MIT
// /provenance/<k>_<tool>: one group per tool run (tool, version, git commit, command line, start
// and end time, MPI ranks, threads, exit status).
#pragma once

#include "core/tool.hpp"

namespace pd::h5 {
class File;
}

namespace pd::store {

/// Appends one provenance entry for `run` ending now with `exit_status`.
void append_provenance(h5::File& f, const RunInfo& run, int exit_status);

} // namespace pd::store
