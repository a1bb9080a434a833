#include "stereo_rig.hpp"

#include <cmath>

namespace gt::render {

glm::vec2 pixelOfDirection(glm::vec3 d, const display::EyeTangents& t, uint32_t w, uint32_t h) {
    const float z = std::max(d.z, 1e-6f);
    const float tx = d.x / z, ty = d.y / z;
    return {(tx - t.left) / (t.right - t.left) * static_cast<float>(w),
            (t.up - ty) / (t.up - t.down) * static_cast<float>(h)};
}

glm::vec3 directionOfPixel(glm::vec2 p, const display::EyeTangents& t, uint32_t w, uint32_t h) {
    const float tx = t.left + p.x / static_cast<float>(w) * (t.right - t.left);
    const float ty = t.up - p.y / static_cast<float>(h) * (t.up - t.down);
    return glm::normalize(glm::vec3(tx, ty, 1.0f));
}

glm::vec3 directionOfAngles(glm::vec2 a) {
    const float yaw = glm::radians(a.x), pitch = glm::radians(a.y);
    // As eyetrack::DisplayGeometry: yaw = atan2(x, z), pitch = atan2(y, hypot(x, z)).
    return {std::sin(yaw) * std::cos(pitch), std::sin(pitch), std::cos(yaw) * std::cos(pitch)};
}

glm::vec2 anglesOfDirection(glm::vec3 d) {
    return {glm::degrees(std::atan2(d.x, d.z)),
            glm::degrees(std::atan2(d.y, std::hypot(d.x, d.z)))};
}

glm::vec3 StereoRig::directionOfLeftPixel(glm::vec2 pixel) const {
    return directionOfPixel(pixel, display::eyeTangents(mProfile, 0), mProfile.eyeWidth,
                            mProfile.eyeHeight);
}

std::array<View, 2> StereoRig::views(const scene::Camera& head, const StereoGaze& gaze,
                                     FoveationMethod& method, const PostSettings& post,
                                     float exposure) const {
    const glm::vec3 f = glm::normalize(head.forward);
    glm::vec3 r = glm::cross(f, head.up);
    if (glm::length(r) < 1e-6f) r = glm::cross(f, glm::vec3(0, 0, 1));
    r = glm::normalize(r);
    std::array<View, 2> out;
    for (int eye = 0; eye < 2; ++eye) {
        View& v = out[static_cast<std::size_t>(eye)];
        v.name = eye == 0 ? "left" : "right";
        const float side = eye == 0 ? -0.5f : 0.5f;
        const glm::vec3 offset(side * mProfile.ipdM, 0.0f, 0.0f); // head frame
        v.camera = head;
        v.camera.position = head.position + r * offset.x;
        const display::EyeTangents t = display::eyeTangents(mProfile, eye);
        v.frustum = trace::FrustumTangents{t.left, t.right, t.up, t.down};
        v.width = mProfile.eyeWidth;
        v.height = mProfile.eyeHeight;
        // The fixation point in the head frame, seen from this eye.
        const glm::vec3 dir = gaze.eyeDirection[eye] ? *gaze.eyeDirection[eye]
                              : gaze.vergenceM
                                  ? glm::normalize(gaze.direction) * *gaze.vergenceM - offset
                                  : gaze.direction;
        const glm::vec2 px = pixelOfDirection(dir, t, v.width, v.height);
        v.gaze = glm::clamp(
            px, glm::vec2(0.0f),
            glm::vec2(static_cast<float>(v.width) - 1.0f, static_cast<float>(v.height) - 1.0f));
        v.saccade = gaze.saccade;
        v.method = &method;
        v.post = post;
        if (mDistortion) {
            v.post.lens = LensSettings{mProfile.lens, display::lensCentre(t)};
        }
        v.exposure = exposure;
    }
    return out;
}

} // namespace gt::render
