// SPDX-License-Identifier: MIT
// pd-solve on a full disk (issue 27): the failure is said as such and the file is left valid,
// cut back to its latest checkpoint. Serial runs: after the write the disk refused. Under MPI a
// write refused on one rank leaves the others inside HDF5's collective calls (no rank can undo
// it), so before each frame or checkpoint rank 0 checks that the disk can hold it and every rank
// stops alike when it cannot; the file is then closed collectively and cut back by rank 0.
#pragma once

#include "core/errors.hpp"

#include <mpi.h>

#include <cstdint>
#include <exception>
#include <memory>
#include <string>

namespace pd::h5 {
class File;
}

namespace pd::pipeline {

/// A write pd-solve did not start because the disk cannot hold it; thrown on every rank alike.
class DiskFullError : public InputError {
  public:
    using InputError::InputError;
};

/// True when `e`, a failed write of `file`, comes from a full file system: HDF5's error stack
/// gave ENOSPC, or less than 1 MiB is left beside the file (checked before the reserve is freed).
bool disk_full(const std::exception& e, const std::string& file);

/// Collective under MPI (every rank before the same write): rank 0 looks at the space free beside
/// `file` (statvfs; the run's 16 MB reserve is still held, so that is room beyond it) and every
/// rank gets its answer. Throws DiskFullError on every rank when it is below `bytes` + 10 % + 1
/// MiB for HDF5's metadata; `what` names the write.
void ensure_room(const std::string& file, std::uint64_t bytes, const std::string& what,
                 MPI_Comm comm, int rank);

/// After a write the full disk refused (the 16 MB reserve freed first): removes a checkpoint
/// left incomplete, cuts every frame and observable series back to the latest checkpoint
/// (none: to no frame), closes `f` and throws InputError (exit 2) saying what the file keeps.
[[noreturn]] void end_on_full_disk(h5::File& f, const std::exception& e);

/// The same under MPI after a DiskFullError (collective; the reserve freed first): every rank
/// closes `f`, rank 0 cuts the file `file` back serially, every rank throws rank 0's InputError.
[[noreturn]] void end_on_full_disk(std::unique_ptr<h5::File>& f, const std::string& file,
                                   const std::exception& e, MPI_Comm comm, int rank);

} // namespace pd::pipeline
