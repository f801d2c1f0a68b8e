// SPDX-License-Identifier: MIT
#include "pipeline/run/signals.hpp"

#include <csignal>

namespace pd::pipeline::run {

namespace {

volatile std::sig_atomic_t received = 0;

extern "C" void on_stop_signal(int sig) {
    received = sig;
}

} // namespace

StopSignals::StopSignals() {
    received = 0;
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGTERM, &sa, nullptr);
    sigaction(SIGUSR1, &sa, nullptr);
}

int stop_signal() {
    return static_cast<int>(received);
}

} // namespace pd::pipeline::run
