#include "foveation/point_chunks.hpp"

#include <algorithm>

namespace gt::foveation {

PointChunks::PointChunks(const PointSet& set) {
    const std::vector<Point>& pts = set.points();
    mBounds.reserve((pts.size() + kPoints - 1) / kPoints);
    for (std::size_t first = 0; first < pts.size(); first += kPoints) {
        const std::size_t end = std::min(pts.size(), first + kPoints);
        Bounds b{{pts[first].x, pts[first].y}, {pts[first].x, pts[first].y}, pts[first].spacing};
        for (std::size_t i = first + 1; i < end; ++i) {
            const glm::vec2 p(pts[i].x, pts[i].y);
            b.lo = glm::min(b.lo, p);
            b.hi = glm::max(b.hi, p);
            b.maxSpacing = std::max(b.maxSpacing, pts[i].spacing);
        }
        mBounds.push_back(b);
    }
}

std::vector<uint32_t> PointChunks::onScreen(glm::vec2 offset, uint32_t width, uint32_t height,
                                            float margin, float siteMove) const {
    const glm::vec2 screenLo(-margin);
    const glm::vec2 screenHi =
        glm::vec2(static_cast<float>(width), static_cast<float>(height)) + margin;
    std::vector<uint32_t> kept;
    for (uint32_t c = 0; c < count(); ++c) {
        const Bounds& b = mBounds[c];
        const float reach = std::max(siteMove, 0.0f) * b.maxSpacing + 1.0f;
        const glm::vec2 lo = b.lo + offset - reach, hi = b.hi + offset + reach;
        if (lo.x < screenHi.x && lo.y < screenHi.y && hi.x >= screenLo.x && hi.y >= screenLo.y) {
            kept.push_back(c);
        }
    }
    return kept;
}

} // namespace gt::foveation
