#include "overlay_layout.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace gt::app {

namespace {
constexpr float kMargin = 8.0f;
// At most this share of the window's width and height, and no smaller than this (the title and
// the frame rate stay readable; in a window too small for both it covers what it must).
constexpr glm::vec2 kShare{0.36f, 0.4f};
constexpr glm::vec2 kMinSize{120.0f, 60.0f};
constexpr glm::vec2 kFullSize{280.0f, 360.0f}; // the whole panel at font scale 1

glm::vec2 cornerPosition(int corner, glm::vec2 window, glm::vec2 size) {
    return {corner % 2 == 0 ? kMargin : window.x - kMargin - size.x,
            corner < 2 ? kMargin : window.y - kMargin - size.y};
}
} // namespace

float distanceToPanel(const OverlayLayout& l, glm::vec2 p) {
    const glm::vec2 nearest = glm::clamp(p, l.position, l.position + l.maxSize);
    return glm::length(p - nearest);
}

OverlayLayout overlayLayout(glm::vec2 window, glm::vec2 gaze, float pixelsPerDegree,
                            int keepCorner) {
    if (keepCorner >= 0 && keepCorner < 4) {
        const OverlayLayout kept = overlayLayout(window, gaze, pixelsPerDegree);
        OverlayLayout there = kept;
        there.corner = keepCorner;
        there.position = cornerPosition(keepCorner, window, there.maxSize);
        const float radius = 0.5f * kFineDetailDiameterDeg * pixelsPerDegree;
        return distanceToPanel(there, gaze) > radius ? there : kept;
    }
    OverlayLayout l;
    // 1 below a window of about 1920 x 1080, then whole steps with the window.
    l.fontScale =
        std::clamp(std::floor(std::min(window.x / 1280.0f, window.y / 720.0f) + 0.5f), 1.0f, 3.0f);
    // The corner farthest from the gaze.
    const std::array<glm::vec2, 4> corners{glm::vec2(0.0f), glm::vec2(window.x, 0.0f),
                                           glm::vec2(0.0f, window.y), window};
    float farthest = -1.0f;
    for (int c = 0; c < 4; ++c) {
        const float d = glm::length(corners[static_cast<std::size_t>(c)] - gaze);
        if (d > farthest) {
            farthest = d;
            l.corner = c;
        }
    }
    glm::vec2 size = glm::min(kShare * window, kFullSize * l.fontScale);
    const float radius = 0.5f * kFineDetailDiameterDeg * pixelsPerDegree;
    for (;;) {
        l.maxSize = glm::max(size, glm::min(kMinSize, window - 2.0f * kMargin));
        l.position = cornerPosition(l.corner, window, l.maxSize);
        if (distanceToPanel(l, gaze) > radius || glm::all(glm::lessThanEqual(size, kMinSize))) {
            return l;
        }
        size *= 0.9f;
    }
}

std::string frameRateText(double frameMs) {
    char text[64];
    std::snprintf(text, sizeof text, "%.1f fps  %.1f ms/frame",
                  frameMs > 0.0 ? 1000.0 / frameMs : 0.0, frameMs);
    return text;
}

std::string latencyText(double latencyMs) {
    char text[64];
    std::snprintf(text, sizeof text, "gaze to GPU done %.1f ms", latencyMs);
    return text;
}

} // namespace gt::app
