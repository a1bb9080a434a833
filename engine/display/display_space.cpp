#include "display/display_space.hpp"

#include <algorithm>
#include <cmath>

namespace gt::display {

namespace {
// Rings around the lens centre by normalised radius (pixels, so pixel-square units).
struct Rings {
    glm::vec2 centrePx;
    float rMaxPx;
    [[nodiscard]] int ring(glm::vec2 p) const {
        const float r = glm::length(p - centrePx) / rMaxPx;
        return std::clamp(static_cast<int>(r * 4.0f), 0, 3);
    }
};

Rings rings(glm::vec2 centre, uint32_t w, uint32_t h) {
    const glm::vec2 c = centre * glm::vec2(w, h);
    const float dx = std::max(c.x, static_cast<float>(w) - c.x);
    const float dy = std::max(c.y, static_cast<float>(h) - c.y);
    return {c, std::sqrt(dx * dx + dy * dy)};
}

// The set shifted so its centre of interest (W, H) lies on `gaze`, in whole pixels as the
// renderer shifts it (passes::gazeOffset): the points on screen plus `margin`.
std::vector<glm::vec2> pointsAround(const foveation::PointSet& set, glm::vec2 gaze, float margin) {
    const float w = static_cast<float>(set.params().display.width);
    const float h = static_cast<float>(set.params().display.height);
    const glm::vec2 offset = glm::floor(gaze) - glm::vec2(w, h);
    std::vector<glm::vec2> out;
    for (const foveation::Point& p : set.points()) {
        const glm::vec2 q = glm::vec2(p.x, p.y) + offset;
        if (q.x >= -margin && q.y >= -margin && q.x < w + margin && q.y < h + margin) {
            out.push_back(q);
        }
    }
    return out;
}
} // namespace

std::vector<glm::vec2> panelPointsInImage(const foveation::PointSet& set, glm::vec2 gazePanel,
                                          const LensModel& lens, glm::vec2 centre, float margin) {
    const glm::vec2 size(static_cast<float>(set.params().display.width),
                         static_cast<float>(set.params().display.height));
    std::vector<glm::vec2> points = pointsAround(set, gazePanel, margin);
    for (glm::vec2& q : points) {
        q = lens.sourceOf(q / size, centre, size.x / size.y, 1) * size;
    }
    return points;
}

LayoutComparison compareLayouts(const foveation::PointSet& set, glm::vec2 gazeImage,
                                const LensModel& lens, glm::vec2 centre, float margin) {
    const uint32_t w = set.params().display.width, h = set.params().display.height;
    const glm::vec2 size(static_cast<float>(w), static_cast<float>(h));
    const Rings rg = rings(centre, w, h);
    std::array<double, 4> area{};
    for (uint32_t y = 0; y < h; ++y) {
        for (uint32_t x = 0; x < w; ++x) {
            area[static_cast<std::size_t>(rg.ring({x + 0.5f, y + 0.5f}))] += 1.0;
        }
    }
    // Points per 1000 image pixels in each ring, counting those that land in the image.
    auto density = [&](const std::vector<glm::vec2>& points) {
        std::array<double, 4> d{};
        for (const glm::vec2 q : points) {
            if (q.x >= 0 && q.y >= 0 && q.x < size.x && q.y < size.y) {
                d[static_cast<std::size_t>(rg.ring(q))] += 1.0;
            }
        }
        for (std::size_t i = 0; i < 4; ++i) {
            d[i] = area[i] > 0 ? 1000.0 * d[i] / area[i] : 0.0;
        }
        return d;
    };
    LayoutComparison c;
    // In the image: the set around the gaze's image pixel.
    const std::vector<glm::vec2> inImage = pointsAround(set, gazeImage, margin);
    c.imagePoints = inImage.size();
    c.imageDensity = density(inImage);
    // On the panel: around the panel point that shows the gaze, carried into the image.
    c.gazePanel = lens.displayOf(gazeImage / size, centre, size.x / size.y) * size;
    const std::vector<glm::vec2> onPanel =
        panelPointsInImage(set, c.gazePanel, lens, centre, margin);
    c.panelPoints = onPanel.size();
    c.panelDensity = density(onPanel);
    return c;
}

} // namespace gt::display
