// SPDX-License-Identifier: MIT
// pd-solve on a full disk (issue 27): the failure is said as such and the file is left valid,
// cut back to its latest checkpoint (serial runs; under MPI the message only).
#pragma once

#include <exception>
#include <string>

namespace pd::h5 {
class File;
}

namespace pd::pipeline {

/// True when `e`, a failed write of `file`, comes from a full file system: HDF5's error stack
/// gave ENOSPC, or less than 1 MiB is left beside the file (checked before the reserve is freed).
bool disk_full(const std::exception& e, const std::string& file);

/// After a write the full disk refused (the 16 MB reserve freed first): removes a checkpoint
/// left incomplete, cuts every frame and observable series back to the latest checkpoint
/// (none: to no frame), closes `f` and throws InputError (exit 2) saying what the file keeps.
[[noreturn]] void end_on_full_disk(h5::File& f, const std::exception& e);

} // namespace pd::pipeline
