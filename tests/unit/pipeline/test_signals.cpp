// SPDX-License-Identifier: MIT
// Stop signals: a SIGTERM after a solve's handlers went out of scope (the step loop over, the
// file still being closed) is recorded, not fatal: the default action used to kill pd-solve on
// a complete run (exit -15).
#include "pipeline/run/signals.hpp"

#include <gtest/gtest.h>

#include <csignal>

TEST(StopSignals, ASignalAfterTheSolveIsRecordedNotFatal) {
    {
        const pd::pipeline::run::StopSignals handlers;
        EXPECT_EQ(pd::pipeline::run::stop_signal(), 0);
        std::raise(SIGUSR1);
        EXPECT_EQ(pd::pipeline::run::stop_signal(), SIGUSR1);
    }
    std::raise(SIGTERM); // would end this test binary with the default action
    EXPECT_EQ(pd::pipeline::run::stop_signal(), SIGTERM);
    const pd::pipeline::run::StopSignals again; // a new solve starts with no request
    EXPECT_EQ(pd::pipeline::run::stop_signal(), 0);
}

TEST(StopSignals, InterruptAndHangUpStopLikeTerm) {
    // Ctrl-C and a closed terminal used to kill pd-solve with no checkpoint (issue 27).
    const pd::pipeline::run::StopSignals handlers;
    for (int sig : {SIGINT, SIGHUP, SIGTERM, SIGUSR1}) {
        std::raise(sig);
        EXPECT_EQ(pd::pipeline::run::stop_signal(), sig);
    }
    EXPECT_STREQ(pd::pipeline::run::stop_signal_name(SIGINT), "SIGINT");
    EXPECT_STREQ(pd::pipeline::run::stop_signal_name(SIGHUP), "SIGHUP");
    EXPECT_STREQ(pd::pipeline::run::stop_signal_name(SIGTERM), "SIGTERM");
}
