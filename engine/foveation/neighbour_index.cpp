#include "foveation/neighbour_index.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include "core/error.hpp"

namespace gt::foveation {

namespace {

// Uniform bucket grid over the canvas for ring searches.
struct Buckets {
    float cell;
    int cols, rows;
    std::vector<uint32_t> start; // cols*rows + 1
    std::vector<uint32_t> items;

    Buckets(const std::vector<Point>& pts, uint32_t w, uint32_t h, float c) : cell(c) {
        cols = static_cast<int>(std::ceil(static_cast<float>(w) / c)) + 1;
        rows = static_cast<int>(std::ceil(static_cast<float>(h) / c)) + 1;
        std::vector<uint32_t> count(static_cast<std::size_t>(cols) * rows + 1, 0);
        for (const Point& p : pts)
            ++count[index(p.x, p.y)];
        start.assign(count.size(), 0);
        for (std::size_t i = 1; i < count.size(); ++i)
            start[i] = start[i - 1] + count[i - 1];
        items.resize(pts.size());
        std::vector<uint32_t> fill(start.begin(), start.end() - 1);
        for (uint32_t i = 0; i < pts.size(); ++i)
            items[fill[index(pts[i].x, pts[i].y)]++] = i;
    }
    [[nodiscard]] std::size_t index(float x, float y) const {
        const int cx = std::clamp(static_cast<int>(x / cell), 0, cols - 1);
        const int cy = std::clamp(static_cast<int>(y / cell), 0, rows - 1);
        return static_cast<std::size_t>(cy) * cols + cx;
    }

    // The k nearest points to (x, y), excluding `skip`, nearest first (ties by index).
    void kNearest(const std::vector<Point>& pts, float x, float y, uint32_t k, uint32_t skip,
                  std::vector<std::pair<float, uint32_t>>& out) const {
        out.clear();
        const int cx = std::clamp(static_cast<int>(x / cell), 0, cols - 1);
        const int cy = std::clamp(static_cast<int>(y / cell), 0, rows - 1);
        const int maxRing = std::max(cols, rows);
        for (int ring = 0; ring <= maxRing; ++ring) {
            for (int gy = cy - ring; gy <= cy + ring; ++gy) {
                if (gy < 0 || gy >= rows) continue;
                const bool edgeRow = gy == cy - ring || gy == cy + ring;
                for (int gx = cx - ring; gx <= cx + ring; gx += edgeRow ? 1 : 2 * ring) {
                    if (gx >= 0 && gx < cols) {
                        const std::size_t c = static_cast<std::size_t>(gy) * cols + gx;
                        for (uint32_t j = start[c]; j < start[c + 1]; ++j) {
                            const uint32_t i = items[j];
                            if (i == skip) continue;
                            const float dx = pts[i].x - x, dy = pts[i].y - y;
                            out.emplace_back(dx * dx + dy * dy, i);
                        }
                    }
                    if (ring == 0) break;
                }
            }
            // Everything within `ring * cell` of (x, y) has been seen: stop once the k-th
            // candidate is closer than that.
            if (out.size() >= k) {
                std::nth_element(out.begin(), out.begin() + (k - 1), out.end());
                const float kth = out[k - 1].first;
                const float safe = static_cast<float>(ring) * cell;
                if (kth <= safe * safe) break;
            }
        }
        const std::size_t n = std::min<std::size_t>(k, out.size());
        std::partial_sort(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n), out.end());
        out.resize(n);
    }
};

template <typename Fn> void parallelFor(uint32_t n, Fn fn) {
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t) {
        pool.emplace_back([&, t] {
            for (uint32_t i = t; i < n; i += threads)
                fn(i);
        });
    }
    for (auto& th : pool)
        th.join();
}

} // namespace

NeighbourIndex::NeighbourIndex(const PointSet& set, uint32_t k)
    : mSet(&set), mK(k), mWidth(set.canvasWidth()), mHeight(set.canvasHeight()) {
    if (k == 0 || k > kMaxNeighbours) throw ArgumentError("k must be 1..20");
    const auto start = std::chrono::steady_clock::now();
    const auto& pts = set.points();
    if (pts.size() <= k) throw ArgumentError("point set has too few points for k");
    const Buckets buckets(pts, mWidth, mHeight, 4.0f);
    mNeighbours.assign(pts.size() * k, 0);
    parallelFor(static_cast<uint32_t>(pts.size()), [&](uint32_t i) {
        thread_local std::vector<std::pair<float, uint32_t>> found;
        buckets.kNearest(pts, pts[i].x, pts[i].y, k, i, found);
        for (uint32_t j = 0; j < k; ++j)
            mNeighbours[static_cast<std::size_t>(i) * k + j] = found[j].second;
    });
    mNearest.assign(static_cast<std::size_t>(mWidth) * mHeight, 0);
    parallelFor(mHeight, [&](uint32_t y) {
        thread_local std::vector<std::pair<float, uint32_t>> found;
        for (uint32_t x = 0; x < mWidth; ++x) {
            buckets.kNearest(pts, static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f, 1,
                             ~0u, found);
            mNearest[static_cast<std::size_t>(y) * mWidth + x] = found[0].second;
        }
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
