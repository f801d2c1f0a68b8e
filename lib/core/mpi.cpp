// SPDX-License-Identifier: MIT
#include "core/mpi.hpp"

namespace pd::mpi {

Session::Session(int* argc, char*** argv) {
    int init = 0;
    MPI_Initialized(&init);
    if (!init) {
        int provided = 0;
        MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
        owns_ = true;
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

Session::~Session() {
    int fin = 0;
    MPI_Finalized(&fin);
    if (owns_ && !fin)
        MPI_Finalize();
}

bool all_ok(MPI_Comm comm, bool ok) {
    int mine = ok ? 1 : 0, all = 0;
    MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, comm);
    return all == 1;
}

} // namespace pd::mpi
