#include "display/display_space.hpp"

#include <algorithm>
#include <cmath>

namespace gt::display {

namespace {
struct Rings {
    glm::vec2 centrePx;
    float aspect, rMaxPx;
    // Normalised radius in pixel-square units, as the lens model measures it.
    [[nodiscard]] int ring(glm::vec2 p) const {
        const float r = glm::length(p - centrePx) / rMaxPx;
        return std::clamp(static_cast<int>(r * 4.0f), 0, 3);
    }
};

Rings rings(glm::vec2 centre, uint32_t w, uint32_t h) {
    const glm::vec2 c = centre * glm::vec2(w, h);
    const float dx = std::max(c.x, static_cast<float>(w) - c.x);
    const float dy = std::max(c.y, static_cast<float>(h) - c.y);
    return {c, static_cast<float>(w) / static_cast<float>(h), std::sqrt(dx * dx + dy * dy)};
}
} // namespace

std::vector<glm::vec2> panelPointsInImage(const foveation::PointSet& set, glm::vec2 gazePanel,
                                          const LensModel& lens, glm::vec2 centre, float margin) {
    const float w = static_cast<float>(set.params().display.width);
    const float h = static_cast<float>(set.params().display.height);
    // The canvas's centre of interest (W, H) goes to the gaze, in whole pixels, as the renderer
    // shifts it (passes::gazeOffset).
    const glm::vec2 offset = glm::floor(gazePanel) - glm::vec2(w, h);
    std::vector<glm::vec2> out;
    for (const foveation::Point& p : set.points()) {
        const glm::vec2 q = glm::vec2(p.x, p.y) + offset;
        if (q.x < -margin || q.y < -margin || q.x >= w + margin || q.y >= h + margin) continue;
        const glm::vec2 src = lens.sourceOf(q / glm::vec2(w, h), centre, w / h, 1);
        out.push_back(src * glm::vec2(w, h));
    }
    return out;
}

LayoutComparison compareLayouts(const foveation::PointSet& set, glm::vec2 gazeImage,
                                const LensModel& lens, glm::vec2 centre, float margin) {
    const uint32_t w = set.params().display.width, h = set.params().display.height;
    const Rings rg = rings(centre, w, h);
    std::array<double, 4> area{};
    for (uint32_t y = 0; y < h; ++y) {
        for (uint32_t x = 0; x < w; ++x) {
            area[static_cast<std::size_t>(rg.ring({x + 0.5f, y + 0.5f}))] += 1.0;
        }
    }
    LayoutComparison c;
    const float fw = static_cast<float>(w), fh = static_cast<float>(h);
    // In the image: the set around the gaze's image pixel.
    const glm::vec2 offset = glm::floor(gazeImage) - glm::vec2(fw, fh);
    for (const foveation::Point& p : set.points()) {
        const glm::vec2 q = glm::vec2(p.x, p.y) + offset;
        if (q.x < -margin || q.y < -margin || q.x >= fw + margin || q.y >= fh + margin) continue;
        ++c.imagePoints;
        if (q.x >= 0 && q.y >= 0 && q.x < fw && q.y < fh) {
            c.imageDensity[static_cast<std::size_t>(rg.ring(q))] += 1.0;
        }
    }
    // On the panel: around the panel point that shows the gaze, carried into the image.
    c.gazePanel =
        lens.displayOf(gazeImage / glm::vec2(fw, fh), centre, fw / fh) * glm::vec2(fw, fh);
    const std::vector<glm::vec2> moved = panelPointsInImage(set, c.gazePanel, lens, centre, margin);
    c.panelPoints = moved.size();
    for (const glm::vec2 q : moved) {
        if (q.x >= 0 && q.y >= 0 && q.x < fw && q.y < fh) {
            c.panelDensity[static_cast<std::size_t>(rg.ring(q))] += 1.0;
        }
    }
    for (std::size_t i = 0; i < 4; ++i) {
        c.imageDensity[i] = area[i] > 0 ? 1000.0 * c.imageDensity[i] / area[i] : 0.0;
        c.panelDensity[i] = area[i] > 0 ? 1000.0 * c.panelDensity[i] / area[i] : 0.0;
    }
    return c;
}

} // namespace gt::display
