// SPDX-License-Identifier: MIT
// The OpenMP team of a tool (issue 28): how many threads by default (never more than the cores
// of this rank, fewer on a loaded machine) and a waiting policy that does not burn the cores a
// thread waits on. run_tool() applies both; OMP_NUM_THREADS, OMP_WAIT_POLICY and GOMP_SPINCOUNT
// set by the user win.
#pragma once

#include <string>

namespace pd::threads {

/// What the default thread count is computed from (machine() reads it; tests give their own).
struct Machine {
    int affinity = 1;      ///< CPUs this process may run on (sched_getaffinity)
    int physical = 1;      ///< distinct physical cores among them (hyper-threads counted once)
    int quota = 0;         ///< CPUs of the cgroup's cpu.max quota (0: no quota)
    int online = 1;        ///< CPUs of the machine
    double load = -1;      ///< 1-minute load average (/proc/loadavg); < 0: unknown
    int ranks_on_node = 1; ///< MPI ranks of this run on this machine
};

/// The default and the reason, e.g. "2 cores per rank, 1.3 busy".
struct Choice {
    int threads = 1;
    std::string why;
};

/// The ranks on this node as the MPI launcher's environment says, before MPI_Init (1 if none).
int launcher_local_ranks();

/// The machine as this process sees it (ranks_on_node given by the caller).
Machine machine(int ranks_on_node);

/// The default thread count: the cores of this rank (affinity and cgroup quota shared by the
/// ranks on the node), at most its physical cores, at most the cores the load average leaves
/// free (rounded to nearest, shared by the ranks); at least 1.
Choice default_threads(const Machine& m);

/// Called before MPI and before any OpenMP region: when neither OMP_WAIT_POLICY nor
/// GOMP_SPINCOUNT is set and more than one thread will run (OMP_NUM_THREADS > 1, or the default
/// of default_threads() with launcher_local_ranks()), sets OMP_WAIT_POLICY=passive and
/// re-executes this program with the same arguments (libgomp reads its environment when it is
/// loaded, before main; idle threads then sleep instead of spinning for up to 300 000 polls).
/// Returns when nothing is to be done or the exec failed (then the run goes on as before).
void passive_wait(char** argv);

/// "passive (set by pdgrain)", "passive", "active", "GOMP_SPINCOUNT=..." or "default (spins)".
std::string wait_policy();

} // namespace pd::threads
