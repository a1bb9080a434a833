#include "foveation/pixel_knn_table.hpp"

#include <algorithm>
#include <chrono>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "foveation/point_buckets.hpp"

namespace gt::foveation {

namespace {
using Candidate = std::pair<float, uint32_t>; // squared distance, point index
} // namespace

PixelKnnTable::PixelKnnTable(const PointSet& set, const NeighbourIndex& index, uint32_t k)
    : mK(k), mWidth(set.canvasWidth()), mHeight(set.canvasHeight()) {
    if (k == 0 || k > index.k() + 1) {
        throw ArgumentError("k-NN table: k must be 1.." + std::to_string(index.k() + 1));
    }
    const auto start = std::chrono::steady_clock::now();
    const auto& pts = set.points();
    // Two grids: fine where points are dense (the fovea), coarse where a search radius spans
    // many fine cells (the periphery, spacing up to tens of pixels).
    constexpr float kFine = 4.0f, kCoarse = 32.0f;
    const detail::PointBuckets fine(pts, mWidth, mHeight, kFine);
    const detail::PointBuckets coarse(pts, mWidth, mHeight, kCoarse);
    const uint32_t stored = index.k();
    mIndices.assign(static_cast<std::size_t>(mWidth) * mHeight * k, 0);
    progress::Step step("building the per-pixel k-NN table", mHeight);
    detail::parallelFor(mHeight, [&](uint32_t y) {
        thread_local std::vector<Candidate> found;
        std::vector<float> bound(stored + 1);
        for (uint32_t x = 0; x < mWidth; ++x) {
            const float px = static_cast<float>(x) + 0.5f, py = static_cast<float>(y) + 0.5f;
            const std::size_t pixel = static_cast<std::size_t>(y) * mWidth + x;
            // The nearest point and its stored neighbours are k real points, so the k-th
            // smallest of their distances bounds the true k-th nearest distance.
            const uint32_t q = index.nearest()[pixel];
            auto dist2 = [&](uint32_t i) {
                const float dx = pts[i].x - px, dy = pts[i].y - py;
                return dx * dx + dy * dy;
            };
            bound[0] = dist2(q);
            for (uint32_t j = 0; j < stored; ++j) {
                bound[j + 1] = dist2(index.neighbours()[static_cast<std::size_t>(q) * stored + j]);
            }
            std::nth_element(bound.begin(), bound.begin() + (k - 1), bound.end());
            const float r2 = bound[k - 1];
            found.clear();
            (r2 <= kFine * kFine * 4.0f ? fine : coarse).withinRadius(pts, px, py, r2, found);
            std::partial_sort(found.begin(), found.begin() + k, found.end());
            for (uint32_t j = 0; j < k; ++j) {
                mIndices[pixel * k + j] = found[j].second;
            }
        }
        step.advance();
    });
    mSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<uint32_t> bruteForceKnn(const PointSet& set, float x, float y, uint32_t k) {
    std::vector<Candidate> all;
    const auto& pts = set.points();
    for (uint32_t i = 0; i < pts.size(); ++i) {
        const float dx = pts[i].x - x, dy = pts[i].y - y;
        all.emplace_back(dx * dx + dy * dy, i);
    }
    const auto n = std::min<std::size_t>(k, all.size());
    std::partial_sort(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(n), all.end());
    std::vector<uint32_t> out;
    for (std::size_t i = 0; i < n; ++i) {
        out.push_back(all[i].second);
    }
    return out;
}

} // namespace gt::foveation
