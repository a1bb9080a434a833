#pragma once
// From what OpenXR reports to what the renderer takes: an eye's pose in the reference space
// becomes a scene camera through the scene's placement, its XrFovf becomes the off-axis
// frustum's tangents, and a gaze ray in the head frame becomes each eye's gaze pixel.
// Axes: OpenXR and glTF agree (+X right, +Y up, -Z ahead, metres for OpenXR).
#include <cstdint>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "foveation/contrast_sensitivity.hpp"
#include "openxr.hpp"
#include "scene/scene.hpp"
#include "trace/gpu_scene.hpp"

namespace gt::xr {

// Where the runtime's reference space lies in the scene: its origin at `origin` (scene
// units), its -Z axis turned by `yawRad` about +Y from the scene's -Z, and `scale` scene units
// per metre the head moves (glTF's unit is the metre: 1).
struct ScenePlacement {
    glm::vec3 origin{0.0f};
    float yawRad = 0.0f;
    float scale = 1.0f;
    [[nodiscard]] glm::vec3 point(const XrVector3f& p) const;
    [[nodiscard]] glm::vec3 direction(const glm::vec3& d) const;
    // The placement that puts the reference space's origin at a camera's eye, facing along
    // its forward direction projected on the floor.
    [[nodiscard]] static ScenePlacement facing(const scene::Camera& camera, float scale);
};

[[nodiscard]] glm::quat toQuat(const XrQuaternionf& q) noexcept;
[[nodiscard]] glm::vec3 toVec(const XrVector3f& v) noexcept;

// The camera at an eye's pose (yfov unused: the view carries its frustum).
[[nodiscard]] scene::Camera cameraOfPose(const XrPosef& pose, const ScenePlacement& placement);
// XrFovf's angles as the tangents the tracing passes take.
[[nodiscard]] trace::FrustumTangents tangentsOfFov(const XrFovf& fov);
// The point-set display of an eye image: its pixels (the size the runtime recommends, times
// --resolution-scale) spanning the runtime's horizontal field of view HFOV = angleRight -
// angleLeft, so v = 1 / (2 tan(HFOV / 2)) image widths (foveation::fovDisplayProfile), as for
// the headset profiles. Throws gt::ArgumentError unless 0 < HFOV < 180 degrees.
[[nodiscard]] foveation::DisplayProfile eyeDisplay(const XrFovf& fov, uint32_t width,
                                                   uint32_t height);

// Where a gaze falls in one eye's image (pixels, origin top-left, centres at integers): the
// fixation point `pointHead` (head frame) or, with `atInfinity`, the direction `pointHead`,
// seen from the eye at `eyeInHead` through `fov`. Clamped to the image.
[[nodiscard]] glm::vec2 gazePixel(const glm::vec3& pointHead, bool atInfinity,
                                  const XrPosef& eyeInHead, const XrFovf& fov, uint32_t width,
                                  uint32_t height);
// The head-frame direction of a pixel of an eye's image (a gaze given in the left eye's pixels).
[[nodiscard]] glm::vec3 directionOfPixel(const glm::vec2& pixel, const XrPosef& eyeInHead,
                                         const XrFovf& fov, uint32_t width, uint32_t height);

} // namespace gt::xr
