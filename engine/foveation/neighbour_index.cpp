#include "foveation/neighbour_index.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "foveation/point_buckets.hpp"

namespace gt::foveation {

NeighbourIndex::NeighbourIndex(const PointSet& set, uint32_t k)
    : mSet(&set), mK(k), mWidth(set.canvasWidth()), mHeight(set.canvasHeight()) {
    if (k == 0 || k > kMaxNeighbours) throw ArgumentError("k must be 1..20");
    const auto start = std::chrono::steady_clock::now();
    const auto& pts = set.points();
    if (pts.size() <= k) throw ArgumentError("point set has too few points for k");
    const detail::PointBuckets buckets(pts, mWidth, mHeight, 4.0f);
    mNeighbours.assign(pts.size() * k, 0);
    // Both passes in one step: the points' neighbours, then the canvas rows' nearest points.
    progress::Step step("building the neighbour index", pts.size() / 1024 + mHeight);
    detail::parallelFor(static_cast<uint32_t>(pts.size()), [&](uint32_t i) {
        thread_local std::vector<std::pair<float, uint32_t>> found;
        buckets.kNearest(pts, pts[i].x, pts[i].y, k, i, found);
        for (uint32_t j = 0; j < k; ++j)
            mNeighbours[static_cast<std::size_t>(i) * k + j] = found[j].second;
        if (i % 1024 == 0) step.advance();
    });
    mNearest.assign(static_cast<std::size_t>(mWidth) * mHeight, 0);
    detail::parallelFor(mHeight, [&](uint32_t y) {
        thread_local std::vector<std::pair<float, uint32_t>> found;
        for (uint32_t x = 0; x < mWidth; ++x) {
            buckets.kNearest(pts, static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f, 1,
                             ~0u, found);
            mNearest[static_cast<std::size_t>(y) * mWidth + x] = found[0].second;
        }
        step.advance();
    });
    mSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<uint32_t> NeighbourIndex::query(float x, float y, uint32_t k) const {
    const auto& pts = mSet->points();
    const uint32_t cx = std::min(mWidth - 1, static_cast<uint32_t>(std::max(0.0f, x)));
    const uint32_t cy = std::min(mHeight - 1, static_cast<uint32_t>(std::max(0.0f, y)));
    const uint32_t q = mNearest[static_cast<std::size_t>(cy) * mWidth + cx];
    std::vector<std::pair<float, uint32_t>> cand;
    auto add = [&](uint32_t i) {
        const float dx = pts[i].x - x, dy = pts[i].y - y;
        cand.emplace_back(dx * dx + dy * dy, i);
    };
    add(q);
    for (uint32_t j = 0; j < mK; ++j)
        add(mNeighbours[static_cast<std::size_t>(q) * mK + j]);
    std::sort(cand.begin(), cand.end());
    std::vector<uint32_t> out;
    for (std::size_t i = 0; i < std::min<std::size_t>(k, cand.size()); ++i)
        out.push_back(cand[i].second);
    return out;
}

} // namespace gt::foveation
