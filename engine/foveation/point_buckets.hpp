#pragma once
// Internal to engine/foveation: a uniform bucket grid over a point set's canvas for exact
// nearest-point searches (NeighbourIndex, PixelKnnTable), and the parallel loop every CPU
// build here uses (also the RBF inverses and pixel weights).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <thread>
#include <utility>
#include <vector>

#include "foveation/point_set.hpp"

namespace gt::foveation::detail {

// Uniform bucket grid over the canvas for ring searches.
struct PointBuckets {
    float cell;
    int cols, rows;
    std::vector<uint32_t> start; // cols*rows + 1
    std::vector<uint32_t> items;

    PointBuckets(const std::vector<Point>& pts, uint32_t w, uint32_t h, float c) : cell(c) {
        cols = static_cast<int>(std::ceil(static_cast<float>(w) / c)) + 1;
        rows = static_cast<int>(std::ceil(static_cast<float>(h) / c)) + 1;
        std::vector<uint32_t> count(static_cast<std::size_t>(cols) * rows + 1, 0);
        for (const Point& p : pts) {
            ++count[index(p.x, p.y)];
        }
        start.assign(count.size(), 0);
        for (std::size_t i = 1; i < count.size(); ++i) {
            start[i] = start[i - 1] + count[i - 1];
        }
        items.resize(pts.size());
        std::vector<uint32_t> fill(start.begin(), start.end() - 1);
        for (uint32_t i = 0; i < pts.size(); ++i) {
            items[fill[index(pts[i].x, pts[i].y)]++] = i;
        }
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
                if (gy < 0 || gy >= rows) {
                    continue;
                }
                const bool edgeRow = gy == cy - ring || gy == cy + ring;
                for (int gx = cx - ring; gx <= cx + ring; gx += edgeRow ? 1 : 2 * ring) {
                    if (gx >= 0 && gx < cols) {
                        const std::size_t c = static_cast<std::size_t>(gy) * cols + gx;
                        for (uint32_t j = start[c]; j < start[c + 1]; ++j) {
                            const uint32_t i = items[j];
                            if (i == skip) {
                                continue;
                            }
                            const float dx = pts[i].x - x, dy = pts[i].y - y;
                            out.emplace_back(dx * dx + dy * dy, i);
                        }
                    }
                    if (ring == 0) {
                        break;
                    }
                }
            }
            // Everything within `ring * cell` of (x, y) has been seen: stop once the k-th
            // candidate is closer than that.
            if (out.size() >= k) {
                std::nth_element(out.begin(), out.begin() + (k - 1), out.end());
                const float kth = out[k - 1].first;
                const float safe = static_cast<float>(ring) * cell;
                if (kth <= safe * safe) {
                    break;
                }
            }
        }
        const std::size_t n = std::min<std::size_t>(k, out.size());
        std::partial_sort(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n), out.end());
        out.resize(n);
    }

    // Appends every point within distance sqrt(r2) of (x, y) (boundary included) as
    // (squared distance, index).
    void withinRadius(const std::vector<Point>& pts, float x, float y, float r2,
                      std::vector<std::pair<float, uint32_t>>& out) const {
        const float r = std::sqrt(r2);
        const int x0 = std::clamp(static_cast<int>((x - r) / cell), 0, cols - 1);
        const int x1 = std::clamp(static_cast<int>((x + r) / cell), 0, cols - 1);
        const int y0 = std::clamp(static_cast<int>((y - r) / cell), 0, rows - 1);
        const int y1 = std::clamp(static_cast<int>((y + r) / cell), 0, rows - 1);
        for (int gy = y0; gy <= y1; ++gy) {
            for (int gx = x0; gx <= x1; ++gx) {
                const std::size_t c = static_cast<std::size_t>(gy) * cols + gx;
                for (uint32_t j = start[c]; j < start[c + 1]; ++j) {
                    const uint32_t i = items[j];
                    const float dx = pts[i].x - x, dy = pts[i].y - y;
                    const float d2 = dx * dx + dy * dy;
                    if (d2 <= r2) {
                        out.emplace_back(d2, i);
                    }
                }
            }
        }
    }
};

// Two grids: fine where points are dense (the fovea), coarse where a search radius spans many
// fine cells (the periphery, spacing up to tens of pixels).
struct PointGrids {
    PointBuckets fine, coarse;

    PointGrids(const std::vector<Point>& pts, uint32_t w, uint32_t h)
        : fine(pts, w, h, 4.0f), coarse(pts, w, h, 32.0f) {}
    // The grid whose ring search around (x, y) visits fewest cells and points: the coarse one
    // unless its cell there already holds many points.
    [[nodiscard]] const PointBuckets& around(float x, float y) const {
        const std::size_t c = coarse.index(x, y);
        return coarse.start[c + 1] - coarse.start[c] >= 64 ? fine : coarse;
    }
    [[nodiscard]] const PointBuckets& within(float radius) const {
        return radius <= 6.0f * fine.cell ? fine : coarse;
    }
};

// Threads every build here uses; 0 (the default): one per core. For measurements.
inline std::atomic<unsigned>& buildThreads() {
    static std::atomic<unsigned> threads{0};
    return threads;
}
inline void setBuildThreads(unsigned threads) {
    buildThreads() = threads;
}

template <typename Fn> void parallelFor(uint32_t n, Fn fn) {
    const unsigned threads = buildThreads() != 0
                                 ? buildThreads().load()
                                 : std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t) {
        pool.emplace_back([&, t] {
            for (uint32_t i = t; i < n; i += threads) {
                fn(i);
            }
        });
    }
    for (auto& th : pool) {
        th.join();
    }
}

} // namespace gt::foveation::detail
