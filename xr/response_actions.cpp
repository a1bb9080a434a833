#include "response_actions.hpp"

#include <string>

#include "xr_error.hpp"

namespace gt::xr {

namespace {
constexpr std::string_view kSimple = "/interaction_profiles/khr/simple_controller";
constexpr std::string_view kTouch = "/interaction_profiles/oculus/touch_controller";
constexpr std::string_view kIndex = "/interaction_profiles/valve/index_controller";
constexpr std::string_view kVive = "/interaction_profiles/htc/vive_controller";
} // namespace

// Input paths as the OpenXR 1.0 specification lists them per profile ("Interaction Profile
// Paths"). A boolean action bound to a trigger's value is thresholded by the runtime.
const std::vector<ButtonBinding>& ResponseActions::bindings() {
    static const std::vector<ButtonBinding> table = {
        {kSimple, 0, "/user/hand/left/input/select/click"},
        {kSimple, 1, "/user/hand/right/input/select/click"},
        {kSimple, 2, "/user/hand/left/input/menu/click"},
        {kSimple, 3, "/user/hand/right/input/menu/click"},
        {kTouch, 0, "/user/hand/left/input/trigger/value"},
        {kTouch, 1, "/user/hand/right/input/trigger/value"},
        {kTouch, 2, "/user/hand/left/input/x/click"},
        {kTouch, 2, "/user/hand/right/input/a/click"},
        {kTouch, 3, "/user/hand/left/input/y/click"},
        {kTouch, 3, "/user/hand/right/input/b/click"},
        {kIndex, 0, "/user/hand/left/input/trigger/click"},
        {kIndex, 1, "/user/hand/right/input/trigger/click"},
        {kIndex, 2, "/user/hand/left/input/a/click"},
        {kIndex, 2, "/user/hand/right/input/a/click"},
        {kIndex, 3, "/user/hand/left/input/b/click"},
        {kIndex, 3, "/user/hand/right/input/b/click"},
        {kVive, 0, "/user/hand/left/input/trigger/click"},
        {kVive, 1, "/user/hand/right/input/trigger/click"},
        {kVive, 2, "/user/hand/left/input/trackpad/click"},
        {kVive, 2, "/user/hand/right/input/trackpad/click"},
        {kVive, 3, "/user/hand/left/input/menu/click"},
        {kVive, 3, "/user/hand/right/input/menu/click"},
    };
    return table;
}

ResponseActions::ResponseActions(ActionSets& sets) : mSets(sets) {
    const XrActionSet set = sets.createSet("gazetrace_responses", "gazetrace responses");
    for (uint32_t b = 0; b < kButtons; ++b) {
        const std::string n = std::to_string(b);
        mActions[b] =
            sets.createAction(set, XR_ACTION_TYPE_BOOLEAN_INPUT, "button_" + n, "Answer " + n);
    }
    for (const ButtonBinding& b : bindings()) {
        sets.suggest(std::string(b.profile), mActions.at(b.button), std::string(b.path));
    }
}

std::vector<uint32_t> ResponseActions::pressed() {
    if (!mSets.attached()) {
        return {}; // nothing synced yet
    }
    const auto scope = mSets.session().context().runtimeCalls();
    std::vector<uint32_t> down;
    mActive = 0;
    for (uint32_t b = 0; b < kButtons; ++b) {
        XrActionStateGetInfo get{XR_TYPE_ACTION_STATE_GET_INFO};
        get.action = mActions[b];
        XrActionStateBoolean state{XR_TYPE_ACTION_STATE_BOOLEAN};
        GT_XR_CHECK(xrGetActionStateBoolean(mSets.session().handle(), &get, &state));
        mActive += state.isActive == XR_TRUE ? 1 : 0;
        if (pressBegan(state)) {
            down.push_back(b);
        }
    }
    mPresses += static_cast<uint32_t>(down.size());
    return down;
}

} // namespace gt::xr
