#include "stop_request.hpp"

#include <atomic>
#include <csignal>
#include <cstring>

namespace gt::app {

namespace {

// Lock-free, so storing it is async-signal-safe (a std::mutex or a heap allocation would not be).
std::atomic<int> gStopSignal{0};
static_assert(std::atomic<int>::is_always_lock_free);

void setDisposition(int signal, void (*handler)(int)) {
    struct sigaction action {};
    action.sa_handler = handler;
    sigemptyset(&action.sa_mask);
    // Restarted system calls: a write or a read interrupted by the signal finishes as if nothing
    // happened; the loop sees the request at its next check.
    action.sa_flags = SA_RESTART;
    sigaction(signal, &action, nullptr);
}

void onStopSignal(int signal) {
    int none = 0;
    gStopSignal.compare_exchange_strong(none, signal);
    // The next SIGINT or SIGTERM ends the process at once (sigaction is async-signal-safe).
    setDisposition(SIGINT, SIG_DFL);
    setDisposition(SIGTERM, SIG_DFL);
}

std::string signalName(int signal) {
    if (signal == SIGINT) {
        return "SIGINT";
    }
    if (signal == SIGTERM) {
        return "SIGTERM";
    }
    return "signal " + std::to_string(signal);
}

} // namespace

void installStopHandlers() {
    for (const int signal : {SIGINT, SIGTERM}) {
        // A signal ignored on entry stays ignored: a shell starts background jobs with SIGINT
        // ignored, so that Ctrl-C at the terminal does not reach them, and nohup does the same.
        struct sigaction now {};
        if (sigaction(signal, nullptr, &now) == 0 && now.sa_handler == SIG_IGN) {
            continue;
        }
        setDisposition(signal, onStopSignal);
    }
}

int stopSignal() noexcept {
    return gStopSignal.load(std::memory_order_relaxed);
}

Interrupted::Interrupted(int signal)
    : mSignal(signal), mWhat("interrupted (" + signalName(signal) + ")") {}

void throwIfStopRequested() {
    if (const int signal = stopSignal(); signal != 0) {
        throw Interrupted(signal);
    }
}

bool liveRunEnds(bool live) {
    if (!live) {
        throwIfStopRequested();
    }
    return stopRequested();
}

namespace testing {
void requestStop(int signal) noexcept {
    gStopSignal.store(signal);
}
} // namespace testing

} // namespace gt::app
