#include "foveation/pixel_knn_table.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "foveation/neighbour_index.hpp"
#include "foveation/point_buckets.hpp"

namespace gt::foveation {

namespace {

using Candidate = std::pair<float, uint32_t>; // squared distance, point index

using detail::PointGrids;

// Squared distance from a point to a pixel centre, the one expression every search here uses,
// so that equal distances (and so the order of ties) agree between them.
inline float distance2(const Point& p, float x, float y) {
    const float dx = p.x - x, dy = p.y - y;
    return dx * dx + dy * dy;
}

// Every point that can be among the k nearest of a pixel centre in the block
// [x0, x1) x [y0, y1): if the block's centre c has its k-th nearest point at R, every pixel
// centre within h of c has its k nearest within R + h of it, so within R + 2h of c.
void blockCandidates(const PointGrids& grids, const std::vector<Point>& pts, uint32_t x0,
                     uint32_t y0, uint32_t x1, uint32_t y1, uint32_t k,
                     std::vector<Candidate>& scratch, std::vector<uint32_t>& out) {
    const float cx = 0.5f * static_cast<float>(x0 + x1), cy = 0.5f * static_cast<float>(y0 + y1);
    const float h =
        std::hypot(0.5f * static_cast<float>(x1 - x0 - 1), 0.5f * static_cast<float>(y1 - y0 - 1));
    grids.around(cx, cy).kNearest(pts, cx, cy, k, ~0u, scratch);
    // Half a pixel over the bound absorbs the rounding of float distances.
    const float r = std::sqrt(scratch.back().first) + 2.0f * h + 0.5f;
    scratch.clear();
    grids.within(r).withinRadius(pts, cx, cy, r * r, scratch);
    out.clear();
    for (const Candidate& c : scratch) {
        out.push_back(c.second);
    }
}

// A quarter tile's candidates, positions and indices side by side for the per-pixel search.
// Sorted by distance from the block's centre, with the least squared distance each can have
// from a pixel centre of the block, so that a pixel's search stops once the rest cannot come
// nearer than its k-th.
struct Block {
    std::vector<float> x, y, least2;
    std::vector<uint32_t> index;
};

// Narrows a tile's candidates to those of the block [x0, x1) x [y0, y1) inside it, by the same
// bound from the block's centre (its k nearest are among the tile's candidates, and so is
// everything within its bound: R_q + 2 h_q + |q - c| <= R_c + 2 h_c).
void narrow(const std::vector<Point>& pts, const std::vector<uint32_t>& tile, uint32_t x0,
            uint32_t y0, uint32_t x1, uint32_t y1, uint32_t k, std::vector<float>& d2,
            std::vector<float>& kth, Block& out) {
    const float cx = 0.5f * static_cast<float>(x0 + x1), cy = 0.5f * static_cast<float>(y0 + y1);
    const float h =
        std::hypot(0.5f * static_cast<float>(x1 - x0 - 1), 0.5f * static_cast<float>(y1 - y0 - 1));
    d2.clear();
    for (const uint32_t i : tile) {
        d2.push_back(distance2(pts[i], cx, cy));
    }
    kth = d2;
    std::nth_element(kth.begin(), kth.begin() + (k - 1), kth.end());
    const float r = std::sqrt(kth[k - 1]) + 2.0f * h + 0.5f;
    thread_local std::vector<std::pair<float, std::size_t>> order;
    order.clear();
    for (std::size_t j = 0; j < tile.size(); ++j) {
        if (d2[j] <= r * r) {
            order.emplace_back(d2[j], j);
        }
    }
    std::sort(order.begin(), order.end());
    out.x.clear();
    out.y.clear();
    out.least2.clear();
    out.index.clear();
    for (const auto& [dist2, j] : order) {
        out.x.push_back(pts[tile[j]].x);
        out.y.push_back(pts[tile[j]].y);
        out.index.push_back(tile[j]);
        // |p - s| >= |q - s| - h; a hundredth of a pixel absorbs the rounding.
        const float least = std::sqrt(dist2) - h - 0.01f;
        out.least2.push_back(least > 0.0f ? least * least : 0.0f);
    }
}

// The k smallest (distance, index) of `block` from the pixel centre (px, py), nearest first.
void kNearestOf(const Block& block, float px, float py, uint32_t k, uint32_t* out) {
    std::array<Candidate, PixelKnnTable::kMaxK> best;
    uint32_t n = 0;
    for (std::size_t j = 0; j < block.index.size(); ++j) {
        if (n == k && block.least2[j] > best[k - 1].first) {
            break;
        }
        const float dx = block.x[j] - px, dy = block.y[j] - py; // as distance2
        const Candidate c{dx * dx + dy * dy, block.index[j]};
        if (n == k && !(c < best[k - 1])) {
            continue;
        }
        uint32_t m = std::min(n, k - 1);
        while (m > 0 && c < best[m - 1]) {
            best[m] = best[m - 1];
            --m;
        }
        best[m] = c;
        n = std::min(n + 1, k);
    }
    for (uint32_t j = 0; j < k; ++j) {
        out[j] = best[j].second;
    }
}

// One band of tiles (kTile canvas rows), built on its own so that bands run in parallel and
// join in order: tiles' bases count from the band's first candidate and row.
struct Band {
    std::vector<uint32_t> tiles, candidates;
    std::vector<uint16_t> slots;
    uint32_t maxCandidates = 0;
};

class TileEncoder {
public:
    TileEncoder(uint32_t k, uint32_t slotsPerRow) : mK(k), mSlotsPerRow(slotsPerRow) {}

    void begin() {
        mRows.clear();
        mHashes.clear();
    }
    // Adds a pixel's k nearest (as a set: sorted in place); returns its row in the tile.
    uint8_t add(uint32_t* nearest) {
        std::sort(nearest, nearest + mK);
        uint64_t hash = 1469598103934665603ull;
        for (uint32_t j = 0; j < mK; ++j) {
            hash = (hash ^ nearest[j]) * 1099511628211ull;
        }
        for (std::size_t r = mHashes.size(); r-- > 0;) {
            if (mHashes[r] == hash && std::equal(nearest, nearest + mK, &mRows[r * mK])) {
                return static_cast<uint8_t>(r);
            }
        }
        mHashes.push_back(hash);
        mRows.insert(mRows.end(), nearest, nearest + mK);
        return static_cast<uint8_t>(mHashes.size() - 1);
    }
    // Appends the tile's header, candidates and rows to the band. Each row's slots are stored
    // nearest to the tile's centre (cx, cy) first: every pixel of the tile then reads its set
    // almost in its own nearest-first order, which keeps the shader's insertion sort short.
    void finish(Band& band, const std::vector<Point>& pts, float cx, float cy) {
        band.tiles.push_back(static_cast<uint32_t>(band.candidates.size()));
        band.tiles.push_back(static_cast<uint32_t>(band.slots.size() / mSlotsPerRow));
        mUsed = mRows;
        std::sort(mUsed.begin(), mUsed.end());
        mUsed.erase(std::unique(mUsed.begin(), mUsed.end()), mUsed.end());
        band.candidates.insert(band.candidates.end(), mUsed.begin(), mUsed.end());
        band.maxCandidates = std::max(band.maxCandidates, static_cast<uint32_t>(mUsed.size()));
        for (std::size_t r = 0; r < mHashes.size(); ++r) {
            for (uint32_t j = 0; j < mK; ++j) {
                const uint32_t i = mRows[r * mK + j];
                mOrder[j] = {distance2(pts[i], cx, cy), i};
            }
            std::sort(mOrder.begin(), mOrder.begin() + mK);
            for (uint32_t j = 0; j < mSlotsPerRow; ++j) {
                const auto at =
                    j < mK ? std::lower_bound(mUsed.begin(), mUsed.end(), mOrder[j].second) -
                                 mUsed.begin()
                           : 0;
                band.slots.push_back(static_cast<uint16_t>(at));
            }
        }
    }

private:
    uint32_t mK, mSlotsPerRow;
    std::vector<uint32_t> mRows, mUsed;
    std::vector<uint64_t> mHashes;
    std::array<Candidate, PixelKnnTable::kMaxK> mOrder{};
};

// Joins the bands in order into the table's arrays; returns the bytes per slot.
uint32_t joinBands(std::vector<Band>& bands, uint32_t perRow, std::vector<uint32_t>& tiles,
                   std::vector<uint32_t>& candidates, std::vector<uint8_t>& slots) {
    std::size_t candidateCount = 0, slotCount = 0, tileCount = 0;
    uint32_t widest = 0;
    for (const Band& b : bands) {
        candidateCount += b.candidates.size();
        slotCount += b.slots.size();
        tileCount += b.tiles.size();
        widest = std::max(widest, b.maxCandidates);
    }
    const uint32_t slotBytes = widest <= 256 ? 1 : 2;
    candidates.reserve(candidateCount);
    slots.reserve(slotCount * slotBytes);
    tiles.reserve(tileCount);
    for (Band& b : bands) {
        const auto candidateBase = static_cast<uint32_t>(candidates.size());
        const auto rowBase = static_cast<uint32_t>(slots.size() / (slotBytes * perRow));
        for (std::size_t i = 0; i < b.tiles.size(); i += 2) {
            tiles.push_back(candidateBase + b.tiles[i]);
            tiles.push_back(rowBase + b.tiles[i + 1]);
        }
        candidates.insert(candidates.end(), b.candidates.begin(), b.candidates.end());
        for (const uint16_t s : b.slots) {
            slots.push_back(static_cast<uint8_t>(s & 0xffu));
            if (slotBytes == 2) {
                slots.push_back(static_cast<uint8_t>(s >> 8));
            }
        }
        b = Band{}; // its memory back before the next band grows the table
    }
    return slotBytes;
}

} // namespace

PixelKnnTable::PixelKnnTable(const PointSet& set, uint32_t k)
    : mSet(&set), mK(k), mWidth(set.canvasWidth()), mHeight(set.canvasHeight()) {
    if (k == 0 || k > kMaxK) {
        throw ArgumentError("k-NN table: k must be 1.." + std::to_string(kMaxK));
    }
    const auto& pts = set.points();
    if (pts.size() < k) {
        throw ArgumentError("k-NN table: the point set has fewer than k points");
    }
    const auto start = std::chrono::steady_clock::now();
    const PointGrids grids(pts, mWidth, mHeight);
    const uint32_t tx = tilesX(), ty = tilesY(), perRow = slotsPerRow();
    mPixelRows.assign(static_cast<std::size_t>(mWidth) * mHeight, 0);
    std::vector<Band> bands(ty);
    progress::Step step("building the per-pixel k-NN table", ty);
    detail::parallelFor(ty, [&](uint32_t band) {
        TileEncoder encoder(k, perRow);
        std::vector<Candidate> scratch;
        std::vector<uint32_t> tile;
        std::vector<float> d2, kth;
        Block block;
        std::array<uint32_t, kMaxK> nearest{};
        const uint32_t y0 = band * kTile, y1 = std::min(mHeight, y0 + kTile);
        for (uint32_t t = 0; t < tx; ++t) {
            const uint32_t x0 = t * kTile, x1 = std::min(mWidth, x0 + kTile);
            encoder.begin();
            blockCandidates(grids, pts, x0, y0, x1, y1, k, scratch, tile);
            // Quarters, each with its own candidates: a bound from nearer its pixels admits
            // fewer points than the tile's.
            constexpr uint32_t side = kTile / 2;
            for (uint32_t qy = y0; qy < y1; qy += side) {
                for (uint32_t qx = x0; qx < x1; qx += side) {
                    const uint32_t qx1 = std::min(x1, qx + side), qy1 = std::min(y1, qy + side);
                    narrow(pts, tile, qx, qy, qx1, qy1, k, d2, kth, block);
                    for (uint32_t y = qy; y < qy1; ++y) {
                        for (uint32_t x = qx; x < qx1; ++x) {
                            kNearestOf(block, static_cast<float>(x) + 0.5f,
                                       static_cast<float>(y) + 0.5f, k, nearest.data());
                            mPixelRows[static_cast<std::size_t>(y) * mWidth + x] =
                                encoder.add(nearest.data());
                        }
                    }
                }
            }
            encoder.finish(bands[band], pts, 0.5f * static_cast<float>(x0 + x1),
                           0.5f * static_cast<float>(y0 + y1));
        }
        step.advance();
    });
    mSlotBytes = joinBands(bands, perRow, mTiles, mCandidates, mSlots);
    mSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

PixelKnnTable::PixelKnnTable(const PointSet& set, const NeighbourIndex& index, uint32_t k)
    : PixelKnnTable(set, checkedK(index, k)) {}

void PixelKnnTable::decode(uint32_t x, uint32_t y, std::span<uint32_t> out) const {
    const auto& pts = mSet->points();
    const float px = static_cast<float>(x) + 0.5f, py = static_cast<float>(y) + 0.5f;
    std::array<Candidate, kMaxK> row;
    for (uint32_t j = 0; j < mK; ++j) {
        const uint32_t i = entry(x, y, j);
        row[j] = {distance2(pts[i], px, py), i};
    }
    std::sort(row.begin(), row.begin() + mK);
    for (uint32_t j = 0; j < mK; ++j) {
        out[j] = row[j].second;
    }
}

uint32_t PixelKnnTable::checkedK(const NeighbourIndex& index, uint32_t k) {
    if (k == 0 || k > index.k() + 1) {
        throw ArgumentError("k-NN table: k must be 1.." + std::to_string(index.k() + 1));
    }
    return k;
}

std::vector<uint32_t> bruteForceKnn(const PointSet& set, float x, float y, uint32_t k) {
    std::vector<Candidate> all;
    const auto& pts = set.points();
    for (uint32_t i = 0; i < pts.size(); ++i) {
        all.emplace_back(distance2(pts[i], x, y), i);
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
