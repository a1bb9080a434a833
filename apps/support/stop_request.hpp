#pragma once
// SIGINT and SIGTERM as a request to stop, seen by the loops between their steps. The handler
// only records which signal came (nothing else is async-signal-safe enough to do there); a
// fixed-length run (render, eval, eyesim, ...) then fails with Interrupted at its next check, so
// everything it wrote is undone by the same RAII that undoes any failed run, and a live run (a
// window, a camera, an OpenXR session) ends as if its user had closed it. A second signal gets
// the default action, so a process stuck in one long step can still be killed.
#include <exception>
#include <string>

namespace gt::app {

// Installs the SIGINT and SIGTERM handlers (once, from main); a signal ignored on entry (a
// background job's SIGINT) stays ignored.
void installStopHandlers();

// The signal that asked to stop (SIGINT, SIGTERM), or 0 while none has.
[[nodiscard]] int stopSignal() noexcept;
[[nodiscard]] inline bool stopRequested() noexcept {
    return stopSignal() != 0;
}

// A fixed-length run that was asked to stop: thrown at the loop's next check, caught by main,
// which reports it in one line and exits with 128 + the signal's number, as a shell does.
class Interrupted : public std::exception {
public:
    explicit Interrupted(int signal);
    [[nodiscard]] int signal() const noexcept { return mSignal; }
    [[nodiscard]] int exitStatus() const noexcept { return 128 + mSignal; }
    // "interrupted (SIGINT)"
    [[nodiscard]] const char* what() const noexcept override { return mWhat.c_str(); }

private:
    int mSignal;
    std::string mWhat;
};

// A fixed-length run's check, once per frame or step: throws Interrupted once a stop was asked.
void throwIfStopRequested();

// The check of a loop that is live or not by what it reads (a camera, or a recording): true when
// a live run should end after the current frame, as at the end of its source; throws Interrupted
// when a fixed-length one was asked to stop.
[[nodiscard]] bool liveRunEnds(bool live);

namespace testing {
// Records `signal` as if it had arrived (0 clears it), for tests of the loops.
void requestStop(int signal) noexcept;
} // namespace testing

} // namespace gt::app
