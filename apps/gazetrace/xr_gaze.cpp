#include "xr_gaze.hpp"

#include "stereo_rig.hpp"

namespace gt::app {

// The gaze ray from `origin` along `direction`, fixated at `vergenceM` (0: infinity).
HeadGaze fixation(const glm::vec3& origin, const glm::vec3& direction, double vergenceM) {
    HeadGaze g;
    g.atInfinity = vergenceM <= 0.0;
    g.point = g.atInfinity ? direction : origin + direction * static_cast<float>(vergenceM);
    return g;
}

// gazetrace's own angles (yaw right, pitch up; +Z ahead) in OpenXR's axes (-Z ahead).
glm::vec3 xrDirectionOfAngles(glm::vec2 anglesDeg) {
    const glm::vec3 d = render::directionOfAngles(anglesDeg);
    return {d.x, d.y, -d.z};
}

HeadGaze runtimeHeadGaze(const xr::EyeGazeSample& s, double vergenceM, const xr::Runtime& rt) {
    HeadGaze g = fixation(s.origin, s.direction, vergenceM);
    if (s.time != 0) {
        g.sampled = rt.fromXrTime(s.time);
    }
    return g;
}

std::optional<HeadGaze> ownHeadGaze(GazeInput* input, double tMs, const xr::FrameInfo& frame,
                                    VkExtent2D left, double vergenceM) {
    const std::optional<GazeReading> r = input ? input->read(tMs) : std::nullopt;
    if (!r) {
        return std::nullopt;
    }
    const glm::vec3 dir =
        r->anglesDeg ? xrDirectionOfAngles(*r->anglesDeg)
                     : xr::directionOfPixel(r->screenPx, frame.headViews[0].pose,
                                            frame.headViews[0].fov, left.width, left.height);
    HeadGaze g = fixation(glm::vec3(0.0f), dir, vergenceM);
    for (int e = 0; e < 2; ++e) {
        if (r->eyeAnglesDeg[e]) {
            g.eyeDirection[e] = xrDirectionOfAngles(*r->eyeAnglesDeg[e]);
        }
    }
    g.saccade = r->saccade;
    g.sampled = r->sampled;
    return g;
}

glm::vec2 anglesOfHeadGaze(const HeadGaze& gaze) {
    const glm::vec3 d = gaze.point;
    return render::anglesOfDirection({d.x, d.y, -d.z});
}

render::View eyeView(const xr::FrameInfo& frame, uint32_t e, const HeadGaze& gaze,
                     const xr::ScenePlacement& placement, VkExtent2D size) {
    render::View v;
    const XrView& eye = frame.views[e];
    v.name = e == 0 ? "left" : "right";
    v.camera = xr::cameraOfPose(eye.pose, placement);
    v.camera.yfov = eye.fov.angleUp - eye.fov.angleDown;
    v.frustum = xr::tangentsOfFov(eye.fov);
    v.width = size.width;
    v.height = size.height;
    const bool own = gaze.eyeDirection[e].has_value();
    v.gaze =
        xr::gazePixel(own ? *gaze.eyeDirection[e] : gaze.point, own || gaze.atInfinity,
                      frame.headViews[e].pose, frame.headViews[e].fov, size.width, size.height);
    v.saccade = gaze.saccade;
    return v;
}

} // namespace gt::app
