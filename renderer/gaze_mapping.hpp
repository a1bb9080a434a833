#pragma once
// Where a gaze given as angles lands. Desktop: on the physical screen of the display profile
// (its pixels, width and distance; the desktop profile is 1920 x 1080 pixels, 51 cm wide, seen
// from 59 cm, Guenter et al. 2012's setup), then in the window by the window's position on that
// screen — the scene camera's field of view does not enter. HMD and OpenXR: through each eye's own
// projection (StereoRig, pixelOfDirection). Angles are degrees from the eye's straight-ahead,
// yaw to the right and pitch up with pitch = atan2(y, hypot(x, z)), the convention the eye
// tracker's calibration fits (eyetrack/gaze/display_geometry.hpp).
#include <cstdint>

#include <glm/glm.hpp>

#include "view.hpp"

namespace gt::render {

struct ScreenGeometry {
    uint32_t widthPx = 1920;
    uint32_t heightPx = 1080;
    double widthCm = 51.0;
    double distanceCm = 59.0;
    // The screen pixel seen at these angles (|angle| < 90 degrees), origin top-left.
    [[nodiscard]] glm::vec2 pixelOfAngles(glm::vec2 yawPitchDeg) const;
    [[nodiscard]] glm::vec2 anglesOfPixel(glm::vec2 pixel) const;
};

// A window of `size` centred on the screen (a headless render of the desktop profile at a
// window's size): its top-left corner in screen pixels.
[[nodiscard]] glm::vec2 centredWindowOrigin(const ScreenGeometry& screen, glm::uvec2 size);

// Through the view's own projection (its frustum tangents, or its symmetric field of view):
// a single HMD eye rendered on its own.
[[nodiscard]] glm::vec2 pixelOfAnglesInView(glm::vec2 yawPitchDeg, const View& view);

} // namespace gt::render
