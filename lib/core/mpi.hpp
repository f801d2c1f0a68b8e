// SPDX-License-Identifier: MIT
// RAII MPI session and small collective helpers. Tools open one Session first (STYLE 2.3).
#pragma once

#include <mpi.h>

namespace pd::mpi {

/// True when an MPI launcher (mpirun, srun, hydra) started this process, or PD_MPI=1.
bool launched_by_mpi();

/// MPI_Init_thread on construction (unless already initialised, or not launched_by_mpi(): a
/// process started alone is rank 0 of 1 and never initialises MPI), MPI_Finalize on destruction.
class Session {
  public:
    Session(int* argc, char*** argv);
    ~Session();
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;
    int rank() const { return rank_; }
    int size() const { return size_; }

  private:
    bool owns_ = false;
    int rank_ = 0;
    int size_ = 1;
};

/// True on every rank iff `ok` is true on every rank of `comm` (agree before a collective).
bool all_ok(MPI_Comm comm, bool ok);

} // namespace pd::mpi
