#pragma once
// Eye gaze from the runtime (XR_EXT_eye_gaze_interaction): one pose action bound to
// /user/eyes_ext/input/gaze_ext/pose, in its own action set among the session's (action_sets.hpp:
// attached with the others, synced once a frame by the caller) and located in the head's VIEW
// space at the frame's predicted display time. Its position is between the eyes and its -Z axis is
// the combined gaze ray. The runtime may offer the extension and still report no valid pose (a
// headset without a tracker, Monado's simulated HMD, the user not looking): locate() is then
// empty and the caller falls back to its own gaze source.
#include <optional>

#include <glm/glm.hpp>

#include "action_sets.hpp"
#include "openxr.hpp"
#include "xr_session.hpp"

namespace gt::xr {

struct EyeGazeSample {
    glm::vec3 origin{0.0f};                 // head frame (VIEW space), metres
    glm::vec3 direction{0.0f, 0.0f, -1.0f}; // head frame, OpenXR axes (-Z ahead)
    XrTime time = 0;                        // when the tracker took it (0: not reported)
};

class EyeGaze {
public:
    // Creates its action set and binding in `sets` (before sets.attach()). Only where the
    // runtime supports eye gaze (Runtime::eyeGazeSupported()); `sets` must outlive this.
    explicit EyeGaze(ActionSets& sets);
    ~EyeGaze();
    EyeGaze(const EyeGaze&) = delete;
    EyeGaze& operator=(const EyeGaze&) = delete;

    // The gaze at `displayTime` in the session's VIEW space, or empty when the runtime has no
    // valid pose. After this frame's ActionSets::sync().
    [[nodiscard]] std::optional<EyeGazeSample> locate(XrTime displayTime);

private:
    Session& mSession;
    XrAction mAction = XR_NULL_HANDLE;
    XrSpace mSpace = XR_NULL_HANDLE;
};

} // namespace gt::xr
