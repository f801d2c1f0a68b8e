// SPDX-License-Identifier: MIT
// The default thread count (issue 28): never more than the cores of a rank, fewer on a loaded
// machine, hyper-threads counted once.
#include "core/threads.hpp"

#include <gtest/gtest.h>

namespace {

pd::threads::Machine idle(int cpus) {
    pd::threads::Machine m;
    m.affinity = m.physical = m.online = cpus;
    m.load = 0.0;
    return m;
}

TEST(Threads, IdleMachineUsesEveryCoreOfTheRank) {
    EXPECT_EQ(pd::threads::default_threads(idle(2)).threads, 2);
    EXPECT_EQ(pd::threads::default_threads(idle(8)).threads, 8);
}

TEST(Threads, RanksShareTheCores) {
    auto m = idle(8);
    m.ranks_on_node = 4;
    EXPECT_EQ(pd::threads::default_threads(m).threads, 2);
    m.ranks_on_node = 16; // oversubscribed: one thread each
    EXPECT_EQ(pd::threads::default_threads(m).threads, 1);
    auto bound = idle(8);
    bound.affinity = bound.physical = 1; // mpirun --bind-to core
    bound.ranks_on_node = 2;
    EXPECT_EQ(pd::threads::default_threads(bound).threads, 1);
}

TEST(Threads, LoadedMachinePrefersFewer) {
    auto m = idle(2);
    m.load = 2.8; // three other builds on two cores
    const auto c = pd::threads::default_threads(m);
    EXPECT_EQ(c.threads, 1);
    EXPECT_NE(c.why.find("busy"), std::string::npos) << c.why;
    m = idle(8);
    m.load = 5.2; // about 3 cores free
    EXPECT_EQ(pd::threads::default_threads(m).threads, 3);
}

TEST(Threads, HyperThreadsAndQuotaCountOnce) {
    auto m = idle(8);
    m.physical = 4; // 2 hyper-threads per core
    EXPECT_EQ(pd::threads::default_threads(m).threads, 4);
    auto q = idle(64);
    q.quota = 2; // cgroup cpu.max of 2 CPUs on a big host
    EXPECT_EQ(pd::threads::default_threads(q).threads, 2);
}

TEST(Threads, UnknownLoadIsIgnoredAndNeverZero) {
    auto m = idle(4);
    m.load = -1;
    EXPECT_EQ(pd::threads::default_threads(m).threads, 4);
    m.load = 100;
    EXPECT_EQ(pd::threads::default_threads(m).threads, 1);
}

TEST(Threads, MachineReadsThisProcess) {
    const auto m = pd::threads::machine(1);
    EXPECT_GE(m.affinity, 1);
    EXPECT_GE(m.physical, 1);
    EXPECT_LE(m.physical, m.affinity);
    EXPECT_GE(m.online, m.affinity);
}

} // namespace
