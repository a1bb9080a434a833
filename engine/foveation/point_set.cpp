#include "foveation/point_set.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "foveation/dart_throwing.hpp"

namespace gt::foveation {

namespace {

// A hierarchy of uniform grids (cell sizes 1, 2, 4, ... px). Every point is linked into each
// level; a query of radius r scans the 3x3 cells of the first level whose cells are >= r, so
// its cost stays constant from the dense centre to the sparse periphery.
class MultiGrid {
public:
    MultiGrid(uint32_t w, uint32_t h, float maxRadius) {
        float size = 1.0f;
        while (true) {
            Level l;
            l.cell = size;
            l.cols = static_cast<uint32_t>(std::ceil(static_cast<float>(w) / size)) + 1;
            l.rows = static_cast<uint32_t>(std::ceil(static_cast<float>(h) / size)) + 1;
            l.head.assign(static_cast<std::size_t>(l.cols) * l.rows, -1);
            mLevels.push_back(std::move(l));
            if (size >= maxRadius) break;
            size *= 2.0f;
        }
    }

    // True when a kept point lies closer than p to (x, y).
    [[nodiscard]] bool anyWithin(const std::vector<Point>& pts, float x, float y, float p) const {
        const float r = p;
        std::size_t li = 0;
        while (li + 1 < mLevels.size() && mLevels[li].cell < r)
            ++li;
        const Level& l = mLevels[li];
        const int cx = static_cast<int>(x / l.cell), cy = static_cast<int>(y / l.cell);
        for (int gy = std::max(0, cy - 1); gy <= std::min(static_cast<int>(l.rows) - 1, cy + 1);
             ++gy) {
            for (int gx = std::max(0, cx - 1); gx <= std::min(static_cast<int>(l.cols) - 1, cx + 1);
                 ++gx) {
                for (int32_t i = l.head[static_cast<std::size_t>(gy) * l.cols + gx]; i >= 0;
                     i = l.next[static_cast<std::size_t>(i)]) {
                    const Point& q = pts[static_cast<std::size_t>(i)];
                    const float dx = q.x - x, dy = q.y - y;
                    if (dx * dx + dy * dy < r * r) return true;
                }
            }
        }
        return false;
    }

    void insert(int32_t index, float x, float y) {
        for (Level& l : mLevels) {
            const std::size_t c =
                static_cast<std::size_t>(static_cast<uint32_t>(y / l.cell)) * l.cols +
                static_cast<uint32_t>(x / l.cell);
            l.next.push_back(l.head[c]);
            l.head[c] = index;
        }
    }

private:
    struct Level {
        float cell = 1.0f;
        uint32_t cols = 0, rows = 0;
        std::vector<int32_t> head;
        std::vector<int32_t> next;
    };
    std::vector<Level> mLevels;
};

} // namespace

uint32_t mortonCode(uint32_t x, uint32_t y) noexcept {
    auto spread = [](uint32_t v) {
        v &= 0xFFFFu;
        v = (v | (v << 8)) & 0x00FF00FFu;
        v = (v | (v << 4)) & 0x0F0F0F0Fu;
        v = (v | (v << 2)) & 0x33333333u;
        v = (v | (v << 1)) & 0x55555555u;
        return v;
    };
    return spread(x) | (spread(y) << 1);
}

PointSetGenerator resolvedGenerator(const PointSetParams& params) noexcept {
    if (params.generator != PointSetGenerator::Auto) return params.generator;
    // The desktop profile's 3840 x 2160 canvas, the largest of the thesis-era displays.
    constexpr uint64_t kSequentialCanvasPixels = 3840ull * 2160ull;
    const uint64_t canvas = 4ull * params.display.width * params.display.height;
    return canvas <= kSequentialCanvasPixels ? PointSetGenerator::Sequential
                                             : PointSetGenerator::Tiled;
}

namespace {

// The thesis's generator: every dart in turn over the whole canvas, first series then second.
std::vector<Point> throwDartsSequentially(const PointSetParams& params,
                                          const detail::SpacingTable& spacing,
                                          const PointSet::Progress& progress) {
    const DisplayProfile& d = params.display;
    const float cw = 2.0f * static_cast<float>(d.width), ch = 2.0f * static_cast<float>(d.height);
    const double cx = d.width, cy = d.height;
    MultiGrid grid(static_cast<uint32_t>(cw), static_cast<uint32_t>(ch), spacing.maxSpacing());
    std::vector<Point> pts;
    detail::SplitMix64 rng(params.seed);
    struct Series {
        double x0, y0, w, h;
        uint64_t darts;
    };
    const double cwDouble = cw, chDouble = ch;
    const double sw = 0.8 * d.width, sh = 0.8 * d.height;
    const Series series[2] = {
        {0.0, 0.0, cwDouble, chDouble,
         static_cast<uint64_t>(params.dartsPerCanvasPixel * cwDouble * chDouble)},
        {cx - 0.5 * sw, cy - 0.5 * sh, sw, sh,
         static_cast<uint64_t>(params.dartsPerCentrePixel * sw * sh)}};
    const uint64_t totalDarts = series[0].darts + series[1].darts;
    uint64_t thrown = 0;
    for (const Series& s : series) {
        for (uint64_t i = 0; i < s.darts; ++i, ++thrown) {
            // Before the rejection below: most darts miss, so a report only on an accepted one
            // at a multiple of 2^20 darts came almost never.
            if (progress && (thrown & 0xFFFFF) == 0) {
                progress(static_cast<double>(thrown) / static_cast<double>(totalDarts));
            }
            const double x = s.x0 + rng.uniform() * s.w;
            const double y = s.y0 + rng.uniform() * s.h;
            const float p = spacing.at(x, y);
            const auto fx = static_cast<float>(x), fy = static_cast<float>(y);
            if (fx >= cw || fy >= ch || grid.anyWithin(pts, fx, fy, p)) continue;
            grid.insert(static_cast<int32_t>(pts.size()), fx, fy);
            pts.push_back({fx, fy, p});
        }
    }
    return pts;
}

} // namespace

PointSet PointSet::generate(const PointSetParams& params, const Progress& progress,
                            unsigned threads) {
    const DisplayProfile& d = params.display;
    if (d.width == 0 || d.height == 0 || d.width > 16384 || d.height > 16384) {
        throw ArgumentError("point set: display size must be 1..16384 pixels");
    }
    if (!(params.scale > 0.0) || params.scale > 100.0) {
        throw ArgumentError("point set: scale must be in (0, 100]");
    }
    if (!(params.minSpacing >= 0.0) || params.minSpacing > 2.0 * (d.width + d.height)) {
        throw ArgumentError("point set: the spacing floor must be in [0, canvas size]");
    }
    const detail::SpacingTable spacing(params);
    std::vector<Point> pts = resolvedGenerator(params) == PointSetGenerator::Tiled
                                 ? detail::throwDartsTiled(params, spacing, progress, threads)
                                 : throwDartsSequentially(params, spacing, progress);
    if (progress) progress(1.0);
    return fromPoints(params, std::move(pts));
}

PointSet PointSet::fromPoints(const PointSetParams& params, std::vector<Point> points) {
    const auto cw = static_cast<float>(2 * params.display.width);
    const auto ch = static_cast<float>(2 * params.display.height);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Point& q = points[i];
        if (!(q.x >= 0.0f && q.x < cw && q.y >= 0.0f && q.y < ch)) {
            throw ArgumentError("point set: point " + std::to_string(i) +
                                " lies outside the canvas (or is not a number)");
        }
    }
    std::vector<std::pair<uint32_t, uint32_t>> keys(points.size());
    for (uint32_t i = 0; i < points.size(); ++i) {
        keys[i] = {
            mortonCode(static_cast<uint32_t>(points[i].x), static_cast<uint32_t>(points[i].y)), i};
    }
    std::sort(keys.begin(), keys.end());
    PointSet set;
    set.mParams = params;
    set.mPoints.reserve(points.size());
    for (const auto& k : keys)
        set.mPoints.push_back(points[k.second]);
    return set;
}

std::size_t PointSet::countOnScreen(float gazeX, float gazeY, float margin) const {
    const float ox = gazeX - static_cast<float>(mParams.display.width);
    const float oy = gazeY - static_cast<float>(mParams.display.height);
    const float w = static_cast<float>(mParams.display.width);
    const float h = static_cast<float>(mParams.display.height);
    std::size_t n = 0;
    for (const Point& p : mPoints) {
        const float x = p.x + ox, y = p.y + oy;
        n += x >= -margin && x < w + margin && y >= -margin && y < h + margin;
    }
    return n;
}

std::size_t PointSet::countOnScreenWithin(float gazeX, float gazeY, float radius,
                                          float margin) const {
    const float w = static_cast<float>(mParams.display.width);
    const float h = static_cast<float>(mParams.display.height);
    const float ox = gazeX - w, oy = gazeY - h;
    std::size_t n = 0;
    for (const Point& p : mPoints) {
        const float x = p.x + ox, y = p.y + oy;
        const float dx = p.x - w, dy = p.y - h;
        n += x >= -margin && x < w + margin && y >= -margin && y < h + margin &&
             dx * dx + dy * dy <= radius * radius;
    }
    return n;
}

PointSetStats PointSet::stats(float margin) const {
    const auto w = static_cast<float>(mParams.display.width);
    const auto h = static_cast<float>(mParams.display.height);
    return {mPoints.size(), countOnScreen(0.5f * w, 0.5f * h, margin), countOnScreen(w, h, margin)};
}

} // namespace gt::foveation
