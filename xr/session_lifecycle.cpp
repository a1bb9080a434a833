#include "session_lifecycle.hpp"

namespace gt::xr {

std::string stateName(XrSessionState state) {
    switch (state) {
    case XR_SESSION_STATE_UNKNOWN:
        return "UNKNOWN";
    case XR_SESSION_STATE_IDLE:
        return "IDLE";
    case XR_SESSION_STATE_READY:
        return "READY";
    case XR_SESSION_STATE_SYNCHRONIZED:
        return "SYNCHRONIZED";
    case XR_SESSION_STATE_VISIBLE:
        return "VISIBLE";
    case XR_SESSION_STATE_FOCUSED:
        return "FOCUSED";
    case XR_SESSION_STATE_STOPPING:
        return "STOPPING";
    case XR_SESSION_STATE_LOSS_PENDING:
        return "LOSS_PENDING";
    case XR_SESSION_STATE_EXITING:
        return "EXITING";
    default:
        return "STATE " + std::to_string(static_cast<int>(state));
    }
}

LifecycleAction SessionLifecycle::onStateChanged(XrSessionState state) {
    mState = state;
    mHistory.push_back(stateName(state));
    switch (state) {
    case XR_SESSION_STATE_READY:
        // READY again after STOPPING (the runtime took the display away and gives it back) is a
        // new begin, unless we asked to leave.
        return mRunning || mExitRequested ? LifecycleAction::None : LifecycleAction::BeginSession;
    case XR_SESSION_STATE_FOCUSED:
        mFocusedOnce = true;
        return LifecycleAction::None;
    case XR_SESSION_STATE_STOPPING:
        return mRunning ? LifecycleAction::EndSession : LifecycleAction::None;
    case XR_SESSION_STATE_EXITING:
        return LifecycleAction::Exit;
    case XR_SESSION_STATE_LOSS_PENDING:
        return LifecycleAction::Lost;
    default:
        return LifecycleAction::None;
    }
}

} // namespace gt::xr
