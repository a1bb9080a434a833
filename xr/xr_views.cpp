#include "xr_views.hpp"

#include "stereo_rig.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gt::xr {

glm::quat toQuat(const XrQuaternionf& q) noexcept {
    return {q.w, q.x, q.y, q.z};
}

glm::vec3 toVec(const XrVector3f& v) noexcept {
    return {v.x, v.y, v.z};
}

glm::vec3 ScenePlacement::direction(const glm::vec3& d) const {
    const float c = std::cos(yawRad), s = std::sin(yawRad);
    // A turn about +Y by yawRad (counter-clockwise seen from above, as glTF's rotations).
    return {c * d.x + s * d.z, d.y, -s * d.x + c * d.z};
}

glm::vec3 ScenePlacement::point(const XrVector3f& p) const {
    return origin + direction(toVec(p) * scale);
}

ScenePlacement ScenePlacement::facing(const scene::Camera& camera, float scale) {
    ScenePlacement p;
    p.origin = camera.position;
    p.scale = scale;
    const glm::vec3 f = camera.forward;
    // The turn that takes -Z to f's horizontal part; straight up or down keeps the scene's axes.
    p.yawRad = std::hypot(f.x, f.z) > 1e-6f ? std::atan2(-f.x, -f.z) : 0.0f;
    return p;
}

scene::Camera cameraOfPose(const XrPosef& pose, const ScenePlacement& placement) {
    const glm::quat q = toQuat(pose.orientation);
    scene::Camera c;
    c.position = placement.point(pose.position);
    c.forward = glm::normalize(placement.direction(q * glm::vec3(0.0f, 0.0f, -1.0f)));
    c.up = glm::normalize(placement.direction(q * glm::vec3(0.0f, 1.0f, 0.0f)));
    return c;
}

trace::FrustumTangents tangentsOfFov(const XrFovf& fov) {
    return {std::tan(fov.angleLeft), std::tan(fov.angleRight), std::tan(fov.angleUp),
            std::tan(fov.angleDown)};
}

foveation::DisplayProfile eyeDisplay(const XrFovf& fov, uint32_t width, uint32_t height) {
    const double hfovDeg =
        (static_cast<double>(fov.angleRight) - static_cast<double>(fov.angleLeft)) * 180.0 /
        std::numbers::pi;
    return foveation::fovDisplayProfile("xr", width, height, hfovDeg);
}

namespace {
// The renderer's pixel <-> direction maths (renderer/stereo_rig.hpp) works in an eye frame with
// +Z ahead; OpenXR's has -Z ahead.
glm::vec3 flipZ(const glm::vec3& d) {
    return {d.x, d.y, -d.z};
}

display::EyeTangents eyeTangents(const XrFovf& fov) {
    const trace::FrustumTangents t = tangentsOfFov(fov);
    return {t.left, t.right, t.up, t.down};
}
} // namespace

glm::vec2 gazePixel(const glm::vec3& pointHead, bool atInfinity, const XrPosef& eyeInHead,
                    const XrFovf& fov, uint32_t width, uint32_t height) {
    const glm::quat q = toQuat(eyeInHead.orientation);
    const glm::vec3 inEye =
        glm::inverse(q) * (atInfinity ? pointHead : pointHead - toVec(eyeInHead.position));
    const glm::vec2 px = render::pixelOfDirection(flipZ(inEye), eyeTangents(fov), width, height);
    return glm::clamp(
        px, glm::vec2(0.0f),
        glm::vec2(static_cast<float>(width) - 1.0f, static_cast<float>(height) - 1.0f));
}

glm::vec3 directionOfPixel(const glm::vec2& pixel, const XrPosef& eyeInHead, const XrFovf& fov,
                           uint32_t width, uint32_t height) {
    const glm::vec3 inEye = render::directionOfPixel(pixel, eyeTangents(fov), width, height);
    return glm::normalize(toQuat(eyeInHead.orientation) * flipZ(inEye));
}

} // namespace gt::xr
