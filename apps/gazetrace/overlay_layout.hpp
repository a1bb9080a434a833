#pragma once
// Where the demo's overlay panel goes: a window-size and gaze -> rectangle function with no
// ImGui in it, so the rule is testable. The panel keeps off the circle of 5 degrees around the
// gaze in which we see fine detail (the foveated ray-tracing thesis, section 2, after Guenter
// et al. 2012): it sits in the window's corner farthest from the gaze, no larger than a share of
// the window, shrunk further until it clears that circle.
#include <string>

#include <glm/glm.hpp>

namespace gt::app {

// The circle of fine detail, fovea and parafovea, in degrees of visual angle (its diameter).
inline constexpr float kFineDetailDiameterDeg = 5.0f;

struct OverlayLayout {
    glm::vec2 position{0.0f}; // the panel's top-left corner, window pixels
    glm::vec2 maxSize{0.0f};  // the panel grows no larger (its content scrolls beyond)
    // Whole multiples of the font's own size only: the default font (ProggyClean, a bitmap
    // font) has one-pixel glyphs, the decimal point among them, that a scale below 1 shrinks
    // under a pixel and the rasteriser drops ("3 2 fps" for "3.2 fps" at 0.85).
    float fontScale = 1.0f;
    int corner = 0; // 0 top-left, 1 top-right, 2 bottom-left, 3 bottom-right
};

// `window`: its size in pixels; `gaze`: window pixels; `pixelsPerDegree`: of the screen the
// window is on, near the gaze. `keepCorner` (0..3): stay in that corner while the panel there
// clears the circle, so the panel does not jump about with every move of the gaze.
[[nodiscard]] OverlayLayout overlayLayout(glm::vec2 window, glm::vec2 gaze, float pixelsPerDegree,
                                          int keepCorner = -1);

// Distance from `p` to the panel's largest rectangle (0 inside it).
[[nodiscard]] float distanceToPanel(const OverlayLayout& layout, glm::vec2 p);

// The overlay's numbers, with one decimal: "3.2 fps  312.5 ms/frame".
[[nodiscard]] std::string frameRateText(double frameMs);
// What the demo's latency measures: from the gaze sample to the frame known finished on the
// device (no present timing is offered, so it is not gaze-to-photon).
[[nodiscard]] std::string latencyText(double latencyMs);

} // namespace gt::app
