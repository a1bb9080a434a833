// The tiled generator (PointSetGenerator::Tiled): the thesis's dart throwing with its
// acceptance rule (a dart at x is kept only if no kept point lies closer than p(x), section
// 4.1), made to scale to a 3840 x 3744 eye by two changes that keep the density:
//
// - Darts in proportion to what saturation needs. The sequential series throw 4 darts per
//   canvas pixel (12 near the centre), which is 4 pi p^2 darts per disc of radius p: about 4 at
//   the centre, where the set is not saturated, and over 900 in the periphery of a large
//   display, where dart throwing saturated long before and nearly every dart is rejected. The
//   tiled generator throws the same darts per pixel, but at most kDartsPerDisc per disc area,
//   and rejects a dart that lands in a cell already inside one point's exclusion disc without
//   a search.
// - Parallel, conflict-free tiles, as in parallel Poisson-disc sampling (Wei 2008): square tiles
//   at least the largest spacing wide; tiles of the same parity class (x and y tile index modulo
//   2) are a whole tile apart, so no dart in one can be rejected by a point of another, and
//   they are filled at once while the other classes (the only ones a dart looks at beyond its
//   own tile) stay still. Each tile draws from its own random stream, so the set depends on
//   the seed alone, not on the threads or their timing. The darts of a tile are spread over
//   kRounds rounds of the four classes, so that no class fills its tiles far ahead of its
//   neighbours.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <thread>

#include "foveation/dart_throwing.hpp"

namespace gt::foveation::detail {

namespace {

// Saturation: random sequential adsorption covers 0.547 of the plane with discs of radius p/2
// as darts per disc grow without bound, and the gap closes only as darts^(-1/2) (Feder's law).
// 256 darts per disc of radius p keep a 3840 x 3744 eye's set within 1 % of the sequential
// generator's count, and rings agree within 3 % (tests/unit/foveation_test.cpp).
constexpr double kDartsPerDisc = 256.0;
constexpr int kRounds = 4;
constexpr float kMinTile = 16.0f;
constexpr double kTwoPowMinus32 = 1.0 / 4294967296.0;

uint64_t mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

struct Tile {
    float x0 = 0, y0 = 0, x1 = 0, y1 = 0; // bounds on the canvas, clipped to it
    float cell = 1;                       // grid cell: the largest spacing in the tile
    uint32_t cols = 0, rows = 0;
    double darts = 0;          // darts over all rounds
    double intensity = 0;      // darts per pixel, the tile's largest
    std::vector<int32_t> head; // per cell, first point (index into points)
    std::vector<int32_t> next; // per point, the next one in its cell
    std::vector<Point> points;
    // Fine cells a third of a grid cell wide, flagged once they lie wholly within the exclusion
    // disc (radius: the tile's smallest spacing) of one of the tile's points: a dart there is
    // rejected without a search, and most darts land there once the tile fills.
    float pNear = 0;
    float fine = 1;
    uint32_t fineCols = 0, fineRows = 0;
    std::vector<uint8_t> covered;

    [[nodiscard]] bool isCovered(float x, float y) const {
        const auto gx = std::min(fineCols - 1, static_cast<uint32_t>((x - x0) / fine));
        const auto gy = std::min(fineRows - 1, static_cast<uint32_t>((y - y0) / fine));
        return covered[static_cast<std::size_t>(gy) * fineCols + gx] != 0;
    }

    void markCovered(const Point& q) {
        const float r = pNear;
        const int maxX = static_cast<int>(fineCols) - 1, maxY = static_cast<int>(fineRows) - 1;
        const int gx0 = std::clamp(static_cast<int>(std::floor((q.x - r - x0) / fine)), 0, maxX);
        const int gx1 = std::clamp(static_cast<int>(std::floor((q.x + r - x0) / fine)), 0, maxX);
        const int gy0 = std::clamp(static_cast<int>(std::floor((q.y - r - y0) / fine)), 0, maxY);
        const int gy1 = std::clamp(static_cast<int>(std::floor((q.y + r - y0) / fine)), 0, maxY);
        for (int gy = gy0; gy <= gy1; ++gy) {
            const float cy0 = y0 + static_cast<float>(gy) * fine;
            const float dy = std::max(std::abs(cy0 - q.y), std::abs(cy0 + fine - q.y));
            for (int gx = gx0; gx <= gx1; ++gx) {
                const float cx0 = x0 + static_cast<float>(gx) * fine;
                // The cell's farthest corner from q inside the open disc: all of it is.
                const float dx = std::max(std::abs(cx0 - q.x), std::abs(cx0 + fine - q.x));
                if (dx * dx + dy * dy < r * r) {
                    covered[static_cast<std::size_t>(gy) * fineCols + gx] = 1;
                }
            }
        }
    }

    void insert(const Point& p) {
        markCovered(p);
        const auto gx = std::min(cols - 1, static_cast<uint32_t>((p.x - x0) / cell));
        const auto gy = std::min(rows - 1, static_cast<uint32_t>((p.y - y0) / cell));
        const std::size_t c = static_cast<std::size_t>(gy) * cols + gx;
        next.push_back(head[c]);
        head[c] = static_cast<int32_t>(points.size());
        points.push_back(p);
    }

    // True when a point of this tile lies closer than r to (x, y).
    [[nodiscard]] bool anyWithin(float x, float y, float r) const {
        if (points.empty()) return false;
        const int maxX = static_cast<int>(cols) - 1, maxY = static_cast<int>(rows) - 1;
        const int gx0 = std::clamp(static_cast<int>(std::floor((x - r - x0) / cell)), 0, maxX);
        const int gx1 = std::clamp(static_cast<int>(std::floor((x + r - x0) / cell)), 0, maxX);
        const int gy0 = std::clamp(static_cast<int>(std::floor((y - r - y0) / cell)), 0, maxY);
        const int gy1 = std::clamp(static_cast<int>(std::floor((y + r - y0) / cell)), 0, maxY);
        for (int gy = gy0; gy <= gy1; ++gy) {
            for (int gx = gx0; gx <= gx1; ++gx) {
                for (int32_t i = head[static_cast<std::size_t>(gy) * cols + gx]; i >= 0;
                     i = next[static_cast<std::size_t>(i)]) {
                    const Point& q = points[static_cast<std::size_t>(i)];
                    const float dx = q.x - x, dy = q.y - y;
                    if (dx * dx + dy * dy < r * r) return true;
                }
            }
        }
        return false;
    }
};

class TiledCanvas {
public:
    TiledCanvas(const PointSetParams& params, const SpacingTable& spacing)
        : mParams(params), mSpacing(spacing),
          mWidth(2.0f * static_cast<float>(params.display.width)),
          mHeight(2.0f * static_cast<float>(params.display.height)),
          mTile(std::max(kMinTile, std::ceil(spacing.maxSpacing()) + 1.0f)),
          mCols(static_cast<uint32_t>(std::ceil(mWidth / mTile))),
          mRows(static_cast<uint32_t>(std::ceil(mHeight / mTile))),
          mTiles(static_cast<std::size_t>(mCols) * mRows) {
        for (uint32_t ty = 0; ty < mRows; ++ty) {
            for (uint32_t tx = 0; tx < mCols; ++tx)
                setUp(tx, ty);
        }
    }

    [[nodiscard]] uint32_t cols() const { return mCols; }
    [[nodiscard]] uint32_t rows() const { return mRows; }

    // Round `round`'s share of tile (tx, ty)'s darts.
    void throwDarts(uint32_t tx, uint32_t ty, int round) {
        const std::size_t index = static_cast<std::size_t>(ty) * mCols + tx;
        Tile& t = mTiles[index];
        const auto first = static_cast<uint64_t>(t.darts * round / kRounds);
        const auto last = static_cast<uint64_t>(t.darts * (round + 1) / kRounds);
        SplitMix64 rng(mix(mParams.seed ^ mix(index * kRounds + static_cast<uint64_t>(round))));
        const double w = t.x1 - t.x0, h = t.y1 - t.y0;
        for (uint64_t i = first; i < last; ++i) {
            // x and y from the two halves of one draw: 2^-32 of a tile is far below float's
            // resolution on the canvas.
            const uint64_t u = rng.next();
            const double x = t.x0 + static_cast<double>(u >> 32) * kTwoPowMinus32 * w;
            const double y = t.y0 + static_cast<double>(u & 0xFFFFFFFFu) * kTwoPowMinus32 * h;
            const auto fx = static_cast<float>(x), fy = static_cast<float>(y);
            if (fx >= t.x1 || fy >= t.y1 || t.isCovered(fx, fy)) continue;
            const double dx = x - mSpacing.centreX(), dy = y - mSpacing.centreY();
            const float p = mSpacing.atDistance(std::sqrt(dx * dx + dy * dy));
            // The tile throws at its largest intensity; thinning to the local one keeps the
            // darts per pixel those of the sequential series, up to kDartsPerDisc per disc.
            if (rng.uniform() * t.intensity >= intensityAt(x, y, p)) continue;
            if (anyWithin(fx, fy, p)) continue;
            t.insert({fx, fy, p});
        }
    }

    // Every tile's points, tile after tile.
    [[nodiscard]] std::vector<Point> points() const {
        std::size_t n = 0;
        for (const Tile& t : mTiles)
            n += t.points.size();
        std::vector<Point> out;
        out.reserve(n);
        for (const Tile& t : mTiles)
            out.insert(out.end(), t.points.begin(), t.points.end());
        return out;
    }

private:
    [[nodiscard]] double intensityAt(double x, double y, float p) const {
        const double perDisc = kDartsPerDisc / (std::numbers::pi * p * p);
        return std::min(dartsPerPixel(mParams, x, y), perDisc);
    }

    void setUp(uint32_t tx, uint32_t ty) {
        Tile& t = mTiles[static_cast<std::size_t>(ty) * mCols + tx];
        t.x0 = static_cast<float>(tx) * mTile;
        t.y0 = static_cast<float>(ty) * mTile;
        t.x1 = std::min(mWidth, t.x0 + mTile);
        t.y1 = std::min(mHeight, t.y0 + mTile);
        // Nearest and farthest tile points from the centre of interest: p grows with distance.
        const double cx = mSpacing.centreX(), cy = mSpacing.centreY();
        const double nx = std::clamp(cx, static_cast<double>(t.x0), static_cast<double>(t.x1));
        const double ny = std::clamp(cy, static_cast<double>(t.y0), static_cast<double>(t.y1));
        const double fx = std::max(std::abs(t.x0 - cx), std::abs(t.x1 - cx));
        const double fy = std::max(std::abs(t.y0 - cy), std::abs(t.y1 - cy));
        const float pNear = mSpacing.atDistance(std::hypot(nx - cx, ny - cy));
        t.cell = std::max(mSpacing.atDistance(std::hypot(fx, fy)), mTile / 64.0f);
        t.cols = static_cast<uint32_t>(std::ceil((t.x1 - t.x0) / t.cell));
        t.rows = static_cast<uint32_t>(std::ceil((t.y1 - t.y0) / t.cell));
        t.head.assign(static_cast<std::size_t>(t.cols) * t.rows, -1);
        t.pNear = pNear;
        t.fine = t.cell / 3.0f;
        t.fineCols = static_cast<uint32_t>(std::ceil((t.x1 - t.x0) / t.fine));
        t.fineRows = static_cast<uint32_t>(std::ceil((t.y1 - t.y0) / t.fine));
        t.covered.assign(static_cast<std::size_t>(t.fineCols) * t.fineRows, 0);
        // The largest darts per pixel anywhere in the tile: the second series' rectangle, if the
        // tile meets it, at the tile's smallest spacing.
        const double sw = 0.8 * mParams.display.width, sh = 0.8 * mParams.display.height;
        const bool meetsCentre = t.x0 < cx + 0.5 * sw && t.x1 > cx - 0.5 * sw &&
                                 t.y0 < cy + 0.5 * sh && t.y1 > cy - 0.5 * sh;
        t.intensity = std::min(mParams.dartsPerCanvasPixel +
                                   (meetsCentre ? mParams.dartsPerCentrePixel : 0.0),
                               kDartsPerDisc / (std::numbers::pi * pNear * pNear));
        t.darts = t.intensity * (t.x1 - t.x0) * (t.y1 - t.y0);
    }

    // Points of every tile within reach: p is less than a tile's width, so at most 2 x 2 tiles,
    // none of them of the class being filled beside this one.
    [[nodiscard]] bool anyWithin(float x, float y, float p) const {
        const int maxX = static_cast<int>(mCols) - 1, maxY = static_cast<int>(mRows) - 1;
        const int tx0 = std::clamp(static_cast<int>((x - p) / mTile), 0, maxX);
        const int tx1 = std::clamp(static_cast<int>((x + p) / mTile), 0, maxX);
        const int ty0 = std::clamp(static_cast<int>((y - p) / mTile), 0, maxY);
        const int ty1 = std::clamp(static_cast<int>((y + p) / mTile), 0, maxY);
        for (int ty = ty0; ty <= ty1; ++ty) {
            for (int tx = tx0; tx <= tx1; ++tx) {
                if (mTiles[static_cast<std::size_t>(ty) * mCols + tx].anyWithin(x, y, p)) {
                    return true;
                }
            }
        }
        return false;
    }

    const PointSetParams& mParams;
    const SpacingTable& mSpacing;
    float mWidth, mHeight, mTile;
    uint32_t mCols, mRows;
    std::vector<Tile> mTiles;
};

// Runs fn(i) for i in [0, n) on `threads` threads, each taking the next undone index.
template <typename Fn> void forEachIndex(std::size_t n, unsigned threads, const Fn& fn) {
    std::atomic<std::size_t> nextIndex{0};
    auto work = [&] {
        for (std::size_t i = nextIndex++; i < n; i = nextIndex++)
            fn(i);
    };
    if (threads <= 1 || n <= 1) {
        work();
        return;
    }
    std::vector<std::jthread> pool;
    for (unsigned t = 1; t < threads; ++t)
        pool.emplace_back(work);
    work();
}

} // namespace

std::vector<Point> throwDartsTiled(const PointSetParams& params, const SpacingTable& spacing,
                                   const PointSet::Progress& progress, unsigned threads) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    TiledCanvas canvas(params, spacing);
    const uint32_t cols = canvas.cols(), rows = canvas.rows();
    constexpr int kClasses = 4;
    for (int round = 0; round < kRounds; ++round) {
        for (int cls = 0; cls < kClasses; ++cls) {
            if (progress)
                progress(static_cast<double>(round * kClasses + cls) / (kRounds * kClasses));
            const uint32_t px = cls & 1, py = cls >> 1;
            const uint32_t classCols = (cols - px + 1) / 2, classRows = (rows - py + 1) / 2;
            forEachIndex(static_cast<std::size_t>(classCols) * classRows, threads,
                         [&](std::size_t i) {
                             const auto tx = px + 2 * static_cast<uint32_t>(i % classCols);
                             const auto ty = py + 2 * static_cast<uint32_t>(i / classCols);
                             canvas.throwDarts(tx, ty, round);
                         });
        }
    }
    return canvas.points();
}

} // namespace gt::foveation::detail
