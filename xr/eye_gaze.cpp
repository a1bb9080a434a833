#include "eye_gaze.hpp"

#include <cstring>

#include <glm/gtc/quaternion.hpp>

#include "xr_error.hpp"

namespace gt::xr {

namespace {
XrPath path(const Runtime& runtime, const char* text) {
    XrPath p = XR_NULL_PATH;
    GT_XR_CHECK(xrStringToPath(runtime.instance(), text, &p));
    return p;
}
} // namespace

EyeGaze::EyeGaze(Session& session) : mSession(session) {
    const auto scope = session.context().runtimeCalls();
    const Runtime& runtime = session.runtime();
    XrActionSetCreateInfo setInfo{XR_TYPE_ACTION_SET_CREATE_INFO};
    std::strncpy(setInfo.actionSetName, "gazetrace", XR_MAX_ACTION_SET_NAME_SIZE - 1);
    std::strncpy(setInfo.localizedActionSetName, "gazetrace",
                 XR_MAX_LOCALIZED_ACTION_SET_NAME_SIZE - 1);
    GT_XR_CHECK(xrCreateActionSet(runtime.instance(), &setInfo, &mActionSet));
    try {
        XrActionCreateInfo actionInfo{XR_TYPE_ACTION_CREATE_INFO};
        actionInfo.actionType = XR_ACTION_TYPE_POSE_INPUT;
        std::strncpy(actionInfo.actionName, "eye_gaze", XR_MAX_ACTION_NAME_SIZE - 1);
        std::strncpy(actionInfo.localizedActionName, "Eye gaze",
                     XR_MAX_LOCALIZED_ACTION_NAME_SIZE - 1);
        GT_XR_CHECK(xrCreateAction(mActionSet, &actionInfo, &mAction));

        XrActionSuggestedBinding binding{mAction,
                                         path(runtime, "/user/eyes_ext/input/gaze_ext/pose")};
        XrInteractionProfileSuggestedBinding suggested{
            XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
        suggested.interactionProfile =
            path(runtime, "/interaction_profiles/ext/eye_gaze_interaction");
        suggested.countSuggestedBindings = 1;
        suggested.suggestedBindings = &binding;
        GT_XR_CHECK(xrSuggestInteractionProfileBindings(runtime.instance(), &suggested));

        XrSessionActionSetsAttachInfo attach{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
        attach.countActionSets = 1;
        attach.actionSets = &mActionSet;
        GT_XR_CHECK(xrAttachSessionActionSets(session.handle(), &attach));

        XrActionSpaceCreateInfo spaceInfo{XR_TYPE_ACTION_SPACE_CREATE_INFO};
        spaceInfo.action = mAction;
        spaceInfo.poseInActionSpace.orientation.w = 1.0f;
        GT_XR_CHECK(xrCreateActionSpace(session.handle(), &spaceInfo, &mSpace));
    } catch (...) {
        if (mSpace != XR_NULL_HANDLE) {
            xrDestroySpace(mSpace);
        }
        xrDestroyActionSet(mActionSet); // destroys its actions too
        throw;
    }
}

EyeGaze::~EyeGaze() {
    const auto scope = mSession.context().runtimeCalls();
    if (mSpace != XR_NULL_HANDLE) {
        xrDestroySpace(mSpace);
    }
    if (mActionSet != XR_NULL_HANDLE) {
        xrDestroyActionSet(mActionSet);
    }
}

std::optional<EyeGazeSample> EyeGaze::locate(XrTime displayTime) {
    const auto scope = mSession.context().runtimeCalls();
    XrActiveActionSet active{mActionSet, XR_NULL_PATH};
    XrActionsSyncInfo sync{XR_TYPE_ACTIONS_SYNC_INFO};
    sync.countActiveActionSets = 1;
    sync.activeActionSets = &active;
    const XrResult synced = xrSyncActions(mSession.handle(), &sync);
    GT_XR_CHECK(synced);
    if (synced == XR_SESSION_NOT_FOCUSED) {
        return std::nullopt; // input goes elsewhere
    }

    XrActionStateGetInfo get{XR_TYPE_ACTION_STATE_GET_INFO};
    get.action = mAction;
    XrActionStatePose state{XR_TYPE_ACTION_STATE_POSE};
    GT_XR_CHECK(xrGetActionStatePose(mSession.handle(), &get, &state));
    if (!state.isActive) {
        return std::nullopt;
    }

    XrEyeGazeSampleTimeEXT sampleTime{XR_TYPE_EYE_GAZE_SAMPLE_TIME_EXT};
    XrSpaceLocation location{XR_TYPE_SPACE_LOCATION};
    location.next = &sampleTime;
    GT_XR_CHECK(xrLocateSpace(mSpace, mSession.viewSpace(), displayTime, &location));
    constexpr XrSpaceLocationFlags valid =
        XR_SPACE_LOCATION_ORIENTATION_VALID_BIT | XR_SPACE_LOCATION_POSITION_VALID_BIT;
    if ((location.locationFlags & valid) != valid) {
        return std::nullopt;
    }
    const XrQuaternionf& q = location.pose.orientation;
    const glm::quat rotation(q.w, q.x, q.y, q.z);
    EyeGazeSample s;
    s.origin = {location.pose.position.x, location.pose.position.y, location.pose.position.z};
    s.direction = glm::normalize(rotation * glm::vec3(0.0f, 0.0f, -1.0f));
    s.time = sampleTime.time;
    return s;
}

} // namespace gt::xr
