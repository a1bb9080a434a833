#include "foveation/neighbour_index.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "foveation/point_buckets.hpp"

namespace gt::foveation {

namespace {
uint32_t checkedK(const PointSet& set, uint32_t k) {
    if (k == 0 || k > NeighbourIndex::kMaxNeighbours) throw ArgumentError("k must be 1..20");
    if (set.points().size() <= k) throw ArgumentError("point set has too few points for k");
    return k;
}
} // namespace

NeighbourIndex::NeighbourIndex(const PointSet& set, uint32_t k)
    : mSet(&set), mK(checkedK(set, k)), mWidth(set.canvasWidth()), mHeight(set.canvasHeight()),
      mNearest(set, 1) {
    const auto start = std::chrono::steady_clock::now();
    const auto& pts = set.points();
    const detail::PointGrids grids(pts, mWidth, mHeight);
    mNeighbours.assign(pts.size() * k, 0);
    progress::Step step("building the neighbour lists", pts.size() / 1024 + 1);
    detail::parallelFor(static_cast<uint32_t>(pts.size()), [&](uint32_t i) {
        thread_local std::vector<std::pair<float, uint32_t>> found;
        grids.around(pts[i].x, pts[i].y).kNearest(pts, pts[i].x, pts[i].y, k, i, found);
        for (uint32_t j = 0; j < k; ++j)
            mNeighbours[static_cast<std::size_t>(i) * k + j] = found[j].second;
        if (i % 1024 == 0) step.advance();
    });
    mSeconds = mNearest.buildSeconds() +
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<uint32_t> NeighbourIndex::nearestPerPixel() const {
    std::vector<uint32_t> out(static_cast<std::size_t>(mWidth) * mHeight);
    detail::parallelFor(mHeight, [&](uint32_t y) {
        for (uint32_t x = 0; x < mWidth; ++x) {
            out[static_cast<std::size_t>(y) * mWidth + x] = mNearest.entry(x, y, 0);
        }
    });
    return out;
}

float NeighbourIndex::coveringRadius() const {
    const auto& pts = mSet->points();
    std::vector<float> rowMax(mHeight, 0.0f);
    detail::parallelFor(mHeight, [&](uint32_t y) {
        float worst = 0.0f;
        for (uint32_t x = 0; x < mWidth; ++x) {
            const Point& q = pts[mNearest.entry(x, y, 0)];
            const float dx = q.x - (static_cast<float>(x) + 0.5f);
            const float dy = q.y - (static_cast<float>(y) + 0.5f);
            worst = std::max(worst, dx * dx + dy * dy);
        }
        rowMax[y] = worst;
    });
    return std::sqrt(*std::max_element(rowMax.begin(), rowMax.end()));
}

std::vector<uint32_t> NeighbourIndex::query(float x, float y, uint32_t k) const {
    const auto& pts = mSet->points();
    const uint32_t cx = std::min(mWidth - 1, static_cast<uint32_t>(std::max(0.0f, x)));
    const uint32_t cy = std::min(mHeight - 1, static_cast<uint32_t>(std::max(0.0f, y)));
    const uint32_t q = mNearest.entry(cx, cy, 0);
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
