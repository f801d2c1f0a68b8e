// SPDX-License-Identifier: MIT
#include "pipeline/run/signals.hpp"

#include <csignal>
#include <initializer_list>

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
    // SIGINT (Ctrl-C) and SIGHUP (the terminal or ssh session closed) stop the run the same way:
    // their default action killed it with no checkpoint and no provenance.
    for (int sig : {SIGTERM, SIGUSR1, SIGINT, SIGHUP})
        sigaction(sig, &sa, nullptr);
}

const char* stop_signal_name(int sig) {
    switch (sig) {
    case SIGUSR1:
        return "SIGUSR1";
    case SIGINT:
        return "SIGINT";
    case SIGHUP:
        return "SIGHUP";
    default:
        return "SIGTERM";
    }
}

int stop_signal() {
    return static_cast<int>(received);
}

} // namespace pd::pipeline::run
