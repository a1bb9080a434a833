#pragma once
// What an OpenXR application does at each session state (OpenXR 1.0 spec, "Session Lifecycle"):
//   IDLE          nothing yet (the runtime is not ready to show us)
//   READY         xrBeginSession: the frame loop starts
//   SYNCHRONIZED  frames are paced but not shown (render nothing: shouldRender is false)
//   VISIBLE       frames are shown, input goes elsewhere
//   FOCUSED       frames are shown and input (eye gaze) reaches us
//   STOPPING      xrEndSession: the frame loop stops
//   LOSS_PENDING  the runtime is losing the session (a service that went away): stop with an error
//   EXITING       the runtime wants the application to end: destroy the session and exit
// Kept apart from the OpenXR calls so the decisions are tested without a runtime.
#include <string>
#include <vector>

#include "openxr.hpp"

namespace gt::xr {

enum class LifecycleAction {
    None,
    BeginSession, // call xrBeginSession now
    EndSession,   // call xrEndSession now
    Exit,         // leave the loop normally (the session is over)
    Lost,         // leave the loop with an error: the runtime lost the session
};

class SessionLifecycle {
public:
    // The runtime reported `state` (XrEventDataSessionStateChanged).
    [[nodiscard]] LifecycleAction onStateChanged(XrSessionState state);
    // xrBeginSession / xrEndSession succeeded.
    void began() noexcept { mRunning = true; }
    void ended() noexcept { mRunning = false; }
    // The application asked to end (xrRequestExitSession was called).
    void exitRequested() noexcept { mExitRequested = true; }

    [[nodiscard]] XrSessionState state() const noexcept { return mState; }
    // Between xrBeginSession and xrEndSession: the frame loop must run (xrWaitFrame etc.).
    [[nodiscard]] bool running() const noexcept { return mRunning; }
    [[nodiscard]] bool focusedOnce() const noexcept { return mFocusedOnce; }
    [[nodiscard]] bool isExitRequested() const noexcept { return mExitRequested; }
    // Every state reported, in order, by name ("READY", "FOCUSED", ...).
    [[nodiscard]] const std::vector<std::string>& history() const noexcept { return mHistory; }

private:
    XrSessionState mState = XR_SESSION_STATE_UNKNOWN;
    bool mRunning = false;
    bool mFocusedOnce = false;
    bool mExitRequested = false;
    std::vector<std::string> mHistory;
};

// "FOCUSED" for XR_SESSION_STATE_FOCUSED.
[[nodiscard]] std::string stateName(XrSessionState state);

} // namespace gt::xr
