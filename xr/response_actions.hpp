#pragma once
// Answer buttons on the controllers: four boolean actions in their own action set among the
// session's (action_sets.hpp), bound on each interaction profile the runtime may offer to inputs
// a hand finds without looking. What a button means is the application's; this reports which
// ones were pressed, each press once (its rising edge), as the frame's ActionSets::sync() saw it.
//
//   button   simple_controller   touch_controller   index_controller   vive_controller
//   0        left select         left trigger       left trigger       left trigger
//   1        right select        right trigger      right trigger      right trigger
//   2        left menu           X or A             A (either hand)    trackpad click (either)
//   3        right menu          Y or B             B (either hand)    menu (either hand)
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "action_sets.hpp"
#include "openxr.hpp"

namespace gt::xr {

// A press is the frame the button went down: the state changed since the last sync and is now
// pressed. A held button is reported once, a release never; an inactive action (no controller
// bound, the session not focused) never.
[[nodiscard]] constexpr bool pressBegan(const XrActionStateBoolean& state) noexcept {
    return state.isActive == XR_TRUE && state.changedSinceLastSync == XR_TRUE &&
           state.currentState == XR_TRUE;
}

// One suggested binding of a button on an interaction profile.
struct ButtonBinding {
    std::string_view profile;
    uint32_t button;
    std::string_view path;
};

class ResponseActions {
public:
    static constexpr uint32_t kButtons = 4;

    // Creates the set, its actions and their bindings in `sets` (before sets.attach()); `sets`
    // must outlive this.
    explicit ResponseActions(ActionSets& sets);

    // The buttons whose press began at this frame's sync, in button order.
    [[nodiscard]] std::vector<uint32_t> pressed();
    // Presses reported so far.
    [[nodiscard]] uint32_t presses() const noexcept { return mPresses; }
    // The buttons bound to an input at the last pressed(): 0 while no controller is bound (none
    // connected, the session not focused, a profile the runtime did not take).
    [[nodiscard]] uint32_t activeButtons() const noexcept { return mActive; }

    // The bindings suggested (the table above).
    [[nodiscard]] static const std::vector<ButtonBinding>& bindings();

private:
    ActionSets& mSets;
    std::array<XrAction, kButtons> mActions{};
    uint32_t mPresses = 0;
    uint32_t mActive = 0;
};

} // namespace gt::xr
