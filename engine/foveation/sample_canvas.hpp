#pragma once
// Where a point set lands on screen (thesis, 4.2): the set lives on a canvas twice the display's
// size and shifts with the gaze; the points that fall on screen, plus a margin, are traced. The
// passes that trace the points and those that rebuild the image from them share this placement.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "display/hmd_profile.hpp"

namespace gt::foveation {

inline constexpr float kSampleMargin = 10.0f; // pixels beyond the screen (thesis 4.2)

// Canvas -> screen offset for a gaze point, in whole pixels (the set shifts by the gaze).
[[nodiscard]] inline glm::vec2 gazeOffset(glm::vec2 gaze, uint32_t displayWidth,
                                          uint32_t displayHeight) {
    return {std::round(gaze.x) - static_cast<float>(displayWidth),
            std::round(gaze.y) - static_cast<float>(displayHeight)};
}

// A frame's ray rotation and site moves as one float, as the shaders read them back: the frame
// number (mod 2^16) plus half the scale s < 2 by which the sites move (site_jitter.glsl).
[[nodiscard]] inline float siteFrameField(uint32_t frame, float siteJitter) {
    return static_cast<float>(frame % (1u << 16)) + 0.5f * std::clamp(siteJitter, 0.0f, 1.9f);
}

// The set laid on an HMD's panel: rays go through the lens model (display/hmd_profile.hpp)
// from their panel position into the image; the gaze is then the panel point that shows it.
struct PanelWarp {
    display::LensModel lens;
    glm::vec2 centre{0.5f};
};

// A panel warp as the shaders take it (shaders/common/panel_warp.glsl): lens = (centre,
// aspect, rMax: the farthest corner's radius), coeffs = (k1, k2, 1 / (1 + k1 + k2), 0).
struct PanelWarpPush {
    glm::vec4 lens{0.0f}, coeffs{0.0f};
};

[[nodiscard]] inline PanelWarpPush panelWarpPush(const PanelWarp& warp, uint32_t width,
                                                 uint32_t height) {
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    const glm::vec2 c = warp.centre;
    const float dx = std::max(c.x, 1.0f - c.x) * aspect, dy = std::max(c.y, 1.0f - c.y);
    return {
        glm::vec4(c, aspect, std::sqrt(dx * dx + dy * dy)),
        glm::vec4(warp.lens.k1, warp.lens.k2, 1.0f / (1.0f + warp.lens.k1 + warp.lens.k2), 0.0f)};
}

} // namespace gt::foveation
