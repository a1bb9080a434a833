#pragma once
// The gaze of an OpenXR frame in the head frame, from the runtime (XR_EXT_eye_gaze_interaction)
// or one of gazetrace's own sources, and each eye's view of a frame with it: shared by
// `gazetrace xr` and the study's xr display.
#include <chrono>
#include <optional>

#include <glm/glm.hpp>

#include "eye_gaze.hpp"
#include "gaze_input.hpp"
#include "view.hpp"
#include "xr_runtime.hpp"
#include "xr_session.hpp"
#include "xr_views.hpp"

namespace gt::app {

// The gaze of one frame in the head frame (OpenXR axes): a fixation point, or a direction
// when the eyes look at infinity.
struct HeadGaze {
    glm::vec3 point{0.0f, 0.0f, -1.0f}; // straight ahead
    bool atInfinity = true;
    // Each tracked eye's own direction (per-eye angle traces, UDP): replaces `point` for it.
    std::optional<glm::vec3> eyeDirection[2];
    bool saccade = false;
    std::optional<std::chrono::steady_clock::time_point> sampled; // when the sample was taken
};

// The gaze ray from `origin` along `direction`, fixated at `vergenceM` (0: infinity).
[[nodiscard]] HeadGaze fixation(const glm::vec3& origin, const glm::vec3& direction,
                                double vergenceM);
// gazetrace's own angles (yaw right, pitch up; +Z ahead) in OpenXR's axes (-Z ahead).
[[nodiscard]] glm::vec3 xrDirectionOfAngles(glm::vec2 anglesDeg);
// The head-frame direction of `gaze` as gazetrace's angles (yaw right, pitch up, degrees).
[[nodiscard]] glm::vec2 anglesOfHeadGaze(const HeadGaze& gaze);
[[nodiscard]] HeadGaze runtimeHeadGaze(const xr::EyeGazeSample& s, double vergenceM,
                                       const xr::Runtime& rt);
// From one of gazetrace's sources (none: straight ahead), empty while the source has no gaze.
// Pixels are the left eye's image's.
[[nodiscard]] std::optional<HeadGaze> ownHeadGaze(GazeInput* input, double tMs,
                                                  const xr::FrameInfo& frame, VkExtent2D left,
                                                  double vergenceM);

// Eye `e`'s view of `frame`: its reported pose through the scene placement, its own field of
// view and size, and the gaze seen through that eye. The method and post settings are the
// caller's.
[[nodiscard]] render::View eyeView(const xr::FrameInfo& frame, uint32_t e, const HeadGaze& gaze,
                                   const xr::ScenePlacement& placement, VkExtent2D size);

} // namespace gt::app
