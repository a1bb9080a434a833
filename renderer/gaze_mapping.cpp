#include "gaze_mapping.hpp"

#include <algorithm>
#include <cmath>

#include "stereo_rig.hpp"

namespace gt::render {

glm::vec2 ScreenGeometry::pixelOfAngles(glm::vec2 a) const {
    constexpr double kLimit = 89.0; // a wild sample must not reach tan's pole
    const double yaw = glm::radians(std::clamp(static_cast<double>(a.x), -kLimit, kLimit));
    const double pitch = glm::radians(std::clamp(static_cast<double>(a.y), -kLimit, kLimit));
    const double x = distanceCm * std::tan(yaw);
    const double y = std::hypot(x, distanceCm) * std::tan(pitch);
    const double cmPerPx = widthCm / widthPx;
    return {static_cast<float>(0.5 * widthPx + x / cmPerPx),
            static_cast<float>(0.5 * heightPx - y / cmPerPx)};
}

glm::vec2 ScreenGeometry::anglesOfPixel(glm::vec2 p) const {
    const double cmPerPx = widthCm / widthPx;
    const double x = (p.x - 0.5 * widthPx) * cmPerPx, y = (0.5 * heightPx - p.y) * cmPerPx;
    return {static_cast<float>(glm::degrees(std::atan2(x, distanceCm))),
            static_cast<float>(glm::degrees(std::atan2(y, std::hypot(x, distanceCm))))};
}

glm::vec2 centredWindowOrigin(const ScreenGeometry& s, glm::uvec2 size) {
    return {0.5f * (static_cast<float>(s.widthPx) - static_cast<float>(size.x)),
            0.5f * (static_cast<float>(s.heightPx) - static_cast<float>(size.y))};
}

glm::vec2 pixelOfAnglesInView(glm::vec2 yawPitchDeg, const View& view) {
    trace::FrustumTangents t =
        view.frustum ? *view.frustum
                     : trace::FrustumTangents::symmetric(view.camera.yfov,
                                                         static_cast<float>(view.width) /
                                                             static_cast<float>(view.height));
    return pixelOfDirection(directionOfAngles(yawPitchDeg), {t.left, t.right, t.up, t.down},
                            view.width, view.height);
}

} // namespace gt::render
