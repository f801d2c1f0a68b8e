// SPDX-License-Identifier: MIT
#include "core/threads.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sched.h>
#include <set>
#include <unistd.h>
#include <utility>

namespace pd::threads {

namespace {

/// A small text file of /proc or /sys (a failed stream if it cannot be read).
std::ifstream open_text(const std::string& path) {
    return std::ifstream(path);
}

/// cgroup v2 cpu.max ("max 100000" or "200000 100000"): the quota in CPUs, rounded up; 0 if none.
int cgroup_quota() {
    auto in = open_text("/sys/fs/cgroup/cpu.max");
    std::string quota;
    double period = 0;
    if (!(in >> quota >> period) || quota == "max" || !(period > 0))
        return 0;
    const double q = std::atof(quota.c_str());
    return q > 0 ? std::max(1, static_cast<int>(std::ceil(q / period))) : 0;
}

} // namespace

int launcher_local_ranks() {
    // Open MPI, MPICH/hydra, Slurm (a step's tasks on this node)
    for (const char* v : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS", "SLURM_NTASKS_PER_NODE"})
        if (const char* n = std::getenv(v); n != nullptr && std::atoi(n) > 0)
            return std::atoi(n);
    return 1;
}

Machine machine(int ranks_on_node) {
    Machine m;
    m.ranks_on_node = std::max(1, ranks_on_node);
    m.online = std::max(1L, sysconf(_SC_NPROCESSORS_ONLN));
    cpu_set_t set;
    CPU_ZERO(&set);
    std::set<std::pair<int, int>> cores; // (package, core) of each CPU we may run on
    if (sched_getaffinity(0, sizeof set, &set) == 0) {
        m.affinity = std::max(1, CPU_COUNT(&set));
        for (int c = 0; c < CPU_SETSIZE; ++c) {
            if (!CPU_ISSET(c, &set))
                continue;
            const std::string dir = fmt::format("/sys/devices/system/cpu/cpu{}/topology/", c);
            int pkg = 0, core = c;
            auto p = open_text(dir + "physical_package_id");
            auto k = open_text(dir + "core_id");
            if (!(p >> pkg) || !(k >> core))
                pkg = -1, core = c; // unknown: count the CPU as a core
            cores.insert({pkg, core});
        }
    } else {
        m.affinity = m.online;
    }
    m.physical = cores.empty() ? m.affinity : static_cast<int>(cores.size());
    m.quota = cgroup_quota();
    auto in = open_text("/proc/loadavg");
    if (double l = 0; in >> l && l >= 0)
        m.load = l;
    return m;
}

Choice default_threads(const Machine& m) {
    const int ranks = std::max(1, m.ranks_on_node);
    // The node's CPUs (online, within the cgroup quota) shared by its ranks, within this rank's
    // affinity (ranks bound to their cores see only those).
    const int node = m.quota > 0 ? std::min(m.online, m.quota) : m.online;
    const int mine = m.quota > 0 ? std::min(m.affinity, m.quota) : m.affinity;
    const int per_rank = std::max(1, std::min(mine, node / ranks));
    // Hyper-threads: the same share of physical cores.
    const int physical =
        std::max(1, per_rank * std::min(m.physical, m.affinity) / std::max(1, m.affinity));
    int n = std::min(per_rank, physical);
    std::string why = fmt::format("{} core(s) per rank", per_rank);
    if (physical < per_rank)
        why += fmt::format(", {} physical", physical);
    if (m.load >= 0) {
        // The load average counts runnable processes (other jobs; our ranks have not run yet).
        const double free = std::max(0.0, static_cast<double>(m.online) - m.load);
        const int free_per_rank = std::max(1, static_cast<int>(std::floor(free / ranks + 0.5)));
        if (free_per_rank < n)
            why += fmt::format(", {:.1f} of {} busy (load average)", m.load, m.online);
        n = std::min(n, free_per_rank);
    }
    return {std::max(1, n), why};
}

void passive_wait(char** argv) {
#ifdef _OPENMP
    if (std::getenv("OMP_WAIT_POLICY") != nullptr || std::getenv("GOMP_SPINCOUNT") != nullptr)
        return; // the user's choice, or set by us before the exec
    if (const char* n = std::getenv("OMP_NUM_THREADS"); n != nullptr && std::atoi(n) == 1)
        return; // no team: nobody waits
    if (std::getenv("OMP_NUM_THREADS") == nullptr &&
        default_threads(machine(launcher_local_ranks())).threads == 1)
        return; // the default is one thread (one core, or a busy machine): no team waits
    setenv("OMP_WAIT_POLICY", "passive", 1);
    setenv("PD_OMP_WAIT_POLICY_SET", "1", 1);
    execv("/proc/self/exe", argv);
    // The exec failed (no /proc): libgomp keeps the policy it read; go on.
    unsetenv("OMP_WAIT_POLICY");
    unsetenv("PD_OMP_WAIT_POLICY_SET");
#else
    (void)argv;
#endif
}

std::string wait_policy() {
    if (const char* s = std::getenv("GOMP_SPINCOUNT"))
        return fmt::format("GOMP_SPINCOUNT={}", s);
    const char* p = std::getenv("OMP_WAIT_POLICY");
    if (p == nullptr)
        return "default (spins)";
    return std::getenv("PD_OMP_WAIT_POLICY_SET") != nullptr ? fmt::format("{} (set by pdgrain)", p)
                                                            : std::string(p);
}

} // namespace pd::threads
