#include "eye_gaze.hpp"

#include <glm/gtc/quaternion.hpp>

#include "xr_error.hpp"

namespace gt::xr {

EyeGaze::EyeGaze(ActionSets& sets) : mSession(sets.session()) {
    const XrActionSet set = sets.createSet("gazetrace", "gazetrace");
    mAction = sets.createAction(set, XR_ACTION_TYPE_POSE_INPUT, "eye_gaze", "Eye gaze");
    sets.suggest("/interaction_profiles/ext/eye_gaze_interaction", mAction,
                 "/user/eyes_ext/input/gaze_ext/pose");
    const auto scope = mSession.context().runtimeCalls();
    XrActionSpaceCreateInfo spaceInfo{XR_TYPE_ACTION_SPACE_CREATE_INFO};
    spaceInfo.action = mAction;
    spaceInfo.poseInActionSpace.orientation.w = 1.0f;
    GT_XR_CHECK(xrCreateActionSpace(mSession.handle(), &spaceInfo, &mSpace));
}

EyeGaze::~EyeGaze() {
    const auto scope = mSession.context().runtimeCalls();
    if (mSpace != XR_NULL_HANDLE) {
        xrDestroySpace(mSpace);
    }
}

std::optional<EyeGazeSample> EyeGaze::locate(XrTime displayTime) {
    const auto scope = mSession.context().runtimeCalls();
    // Not FOCUSED (input goes elsewhere): the last sync left the action inactive.
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
