#include "foveation/pixel_knn_table.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

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
// [x0, x1) x [y0, y1), in ascending index order: if the block's centre c has its k-th nearest
// point within R, every pixel centre within h of c has its k nearest within R + h of it, so
// within R + 2h of c. R is the k-th distance from c among `near` (the previous tile's
// candidates: they hold c's k nearest unless those lie farther than the previous tile's own
// bound, and any k points bound the k-th nearest from above), or by a search where it is empty.
void blockCandidates(const PointGrids& grids, const std::vector<Point>& pts, uint32_t x0,
                     uint32_t y0, uint32_t x1, uint32_t y1, uint32_t k,
                     const std::vector<uint32_t>& near, std::vector<Candidate>& scratch,
                     std::vector<uint32_t>& out) {
    const float cx = 0.5f * static_cast<float>(x0 + x1), cy = 0.5f * static_cast<float>(y0 + y1);
    const float h =
        std::hypot(0.5f * static_cast<float>(x1 - x0 - 1), 0.5f * static_cast<float>(y1 - y0 - 1));
    scratch.clear();
    if (near.size() >= k) {
        for (const uint32_t i : near) {
            scratch.emplace_back(distance2(pts[i], cx, cy), i);
        }
        std::nth_element(scratch.begin(), scratch.begin() + (k - 1), scratch.end());
        scratch.resize(k);
    } else {
        grids.around(cx, cy).kNearest(pts, cx, cy, k, ~0u, scratch);
    }
    // Half a pixel over the bound absorbs the rounding of float distances.
    const float r = std::sqrt(scratch.back().first) + 2.0f * h + 0.5f;
    scratch.clear();
    grids.within(r).withinRadius(pts, cx, cy, r * r, scratch);
    out.clear();
    for (const Candidate& c : scratch) {
        out.push_back(c.second);
    }
    std::sort(out.begin(), out.end());
}

// A quarter tile's candidates, positions and places in the tile's candidates side by side for
// the per-pixel search. The tile's are in index order, so ties order by place as by index.
struct Block {
    std::vector<float> x, y;
    std::vector<uint32_t> at;
};

// Narrows a tile's candidates (their positions) to those of the block [x0, x1) x [y0, y1)
// inside it, by the same bound from the block's centre (its k nearest are among the tile's
// candidates, and so is everything within its bound: R_q + 2 h_q + |q - c| <= R_c + 2 h_c).
void narrow(const Block& tile, uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, uint32_t k,
            std::vector<float>& d2, std::vector<float>& kth, Block& out) {
    const float cx = 0.5f * static_cast<float>(x0 + x1), cy = 0.5f * static_cast<float>(y0 + y1);
    const float h =
        std::hypot(0.5f * static_cast<float>(x1 - x0 - 1), 0.5f * static_cast<float>(y1 - y0 - 1));
    const std::size_t n = tile.x.size();
    d2.resize(n);
    for (std::size_t j = 0; j < n; ++j) {
        const float dx = tile.x[j] - cx, dy = tile.y[j] - cy; // as distance2
        d2[j] = dx * dx + dy * dy;
    }
    kth = d2;
    std::nth_element(kth.begin(), kth.begin() + (k - 1), kth.end());
    const float r = std::sqrt(kth[k - 1]) + 2.0f * h + 0.5f;
    out.x.resize(n);
    out.y.resize(n);
    out.at.resize(n);
    std::size_t kept = 0;
    for (std::size_t j = 0; j < n; ++j) {
        out.x[kept] = tile.x[j];
        out.y[kept] = tile.y[j];
        out.at[kept] = static_cast<uint32_t>(j);
        kept += d2[j] <= r * r ? 1 : 0;
    }
    out.x.resize(kept);
    out.y.resize(kept);
    out.at.resize(kept);
}

// The k nearest of a block's candidates for its pixels in turn. Neighbouring pixels mostly
// share their k nearest, and a set is a pixel's k nearest exactly when its farthest member
// comes before every other candidate (by squared distance, then index): every point that can
// be among the k nearest of a pixel of the block is one of its candidates. So each pixel first
// tests the previous pixel's set, then that set with one member swapped; only where both fail
// does it select again, among the candidates no farther than the set's farthest (the k nearest
// are among them).
class BlockSearch {
public:
    explicit BlockSearch(uint32_t k) : mK(k) {}

    void begin(const Block& block) {
        mBlock = &block;
        mD2.resize(block.at.size());
        mMember.assign(block.at.size(), 0);
        mSet.clear();
    }
    // Searches the pixel centre (px, py); false when its k nearest are the previous pixel's.
    bool search(float px, float py) {
        const Block& b = *mBlock;
        const std::size_t n = b.at.size();
        // In one pass: the farthest two members and the nearest two other candidates.
        constexpr float none = std::numeric_limits<float>::infinity();
        float in = -1.0f, in2 = -1.0f, out = none, out2 = none;
        std::size_t far = 0, near = 0;
        for (std::size_t j = 0; j < n; ++j) {
            const float dx = b.x[j] - px, dy = b.y[j] - py; // as distance2
            const float d2 = dx * dx + dy * dy;
            mD2[j] = d2;
            const bool member = mMember[j] != 0;
            const float asMember = member ? d2 : -1.0f, asOther = member ? none : d2;
            const bool farther = asMember > in, nearer = asOther < out;
            in2 = farther ? in : std::max(in2, asMember);
            far = farther ? j : far;
            in = farther ? asMember : in;
            out2 = nearer ? out : std::min(out2, asOther);
            near = nearer ? j : near;
            out = nearer ? asOther : out;
        }
        if (mSet.empty()) {
            select(none);
            return true;
        }
        if (in < out) {
            return false;
        }
        // Mostly one point overtook one member: then the set with the farthest member swapped
        // for the nearest other candidate passes the same test.
        if (std::max(in2, out) < std::min(out2, in)) {
            mMember[far] = 0;
            mMember[near] = 1;
            *std::find(mSet.begin(), mSet.end(), static_cast<uint32_t>(far)) =
                static_cast<uint32_t>(near);
            return true;
        }
        select(in);
        return true;
    }
    // The current set, as places in the tile's candidates (k).
    void nearest(uint32_t* out) const {
        for (uint32_t j = 0; j < mK; ++j) {
            out[j] = mBlock->at[mSet[j]];
        }
    }

private:
    struct Ranked {
        float d2;
        uint32_t at, j; // place in the tile's candidates (index order), in the block
    };
    static bool before(const Ranked& a, const Ranked& b) {
        return a.d2 < b.d2 || (a.d2 == b.d2 && a.at < b.at);
    }

    // The k smallest (squared distance, index) among the candidates within `bound`. Past the
    // block's first pixel a few more than k lie within it (the previous set and the points
    // that overtook it): those few are dropped, farthest first, instead of sorting.
    void select(float bound) {
        const Block& b = *mBlock;
        mPicked.resize(b.at.size());
        std::size_t picked = 0;
        for (std::size_t j = 0; j < b.at.size(); ++j) {
            mPicked[picked] = {mD2[j], b.at[j], static_cast<uint32_t>(j)};
            picked += mD2[j] <= bound ? 1 : 0;
        }
        mPicked.resize(picked);
        constexpr std::size_t kFewBeyond = 4;
        if (mPicked.size() > mK + kFewBeyond) {
            std::nth_element(mPicked.begin(), mPicked.begin() + (mK - 1), mPicked.end(), before);
            mPicked.resize(mK);
        }
        while (mPicked.size() > mK) {
            auto farthest = mPicked.begin();
            for (auto it = mPicked.begin() + 1; it != mPicked.end(); ++it) {
                farthest = before(*farthest, *it) ? it : farthest;
            }
            *farthest = mPicked.back();
            mPicked.pop_back();
        }
        for (const uint32_t j : mSet) {
            mMember[j] = 0;
        }
        mSet.resize(mK);
        for (uint32_t j = 0; j < mK; ++j) {
            mSet[j] = mPicked[j].j;
            mMember[mPicked[j].j] = 1;
        }
    }

    uint32_t mK;
    const Block* mBlock = nullptr;
    std::vector<float> mD2;
    std::vector<uint8_t> mMember;
    std::vector<uint32_t> mSet; // positions in the block
    std::vector<Ranked> mPicked;
};

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

    // A tile with `candidates` candidates: its rows are bit sets over their places.
    void begin(std::size_t candidates) {
        mWords = (candidates + 63) / 64;
        mRows.clear();
        mRowCount = 0;
    }
    // Adds a pixel's k nearest (places in the tile's candidates); returns its row in the tile.
    uint8_t add(const uint32_t* nearest) {
        mSet.assign(mWords, 0);
        for (uint32_t j = 0; j < mK; ++j) {
            mSet[nearest[j] / 64] |= uint64_t{1} << (nearest[j] % 64);
        }
        for (std::size_t r = mRowCount; r-- > 0;) {
            if (mRows[r * mWords] == mSet[0] &&
                std::equal(mSet.begin() + 1, mSet.end(), mRows.begin() + r * mWords + 1)) {
                return static_cast<uint8_t>(r);
            }
        }
        mRows.insert(mRows.end(), mSet.begin(), mSet.end());
        return static_cast<uint8_t>(mRowCount++);
    }
    // Appends the tile's header, candidates and rows to the band; rows hold places in `tile`,
    // the tile's candidates in index order. Each row's slots are stored nearest to the tile's
    // centre (cx, cy) first: every pixel of the tile then reads its set almost in its own
    // nearest-first order, which keeps the shader's insertion sort short.
    void finish(Band& band, const std::vector<uint32_t>& tile, const std::vector<Point>& pts,
                float cx, float cy) {
        band.tiles.push_back(static_cast<uint32_t>(band.candidates.size()));
        band.tiles.push_back(static_cast<uint32_t>(band.slots.size() / mSlotsPerRow));
        // The candidates some row uses, in index order, and each one's slot among them.
        constexpr uint16_t unused = 0xffffu;
        mSlotOf.assign(tile.size(), unused);
        mSet.assign(mWords, 0);
        for (std::size_t e = 0; e < mRows.size(); ++e) {
            mSet[e % mWords] |= mRows[e];
        }
        mRanked.clear();
        for (std::size_t at = 0; at < tile.size(); ++at) {
            if ((mSet[at / 64] >> (at % 64) & 1u) != 0) {
                mSlotOf[at] = static_cast<uint16_t>(mRanked.size());
                band.candidates.push_back(tile[at]);
                mRanked.emplace_back(distance2(pts[tile[at]], cx, cy), static_cast<uint32_t>(at));
            }
        }
        band.maxCandidates = std::max(band.maxCandidates, static_cast<uint32_t>(mRanked.size()));
        // Each row in the candidates' order from the centre (distance, then index); with at
        // most 64 candidates a row is a bit set of those ranks, read lowest first.
        std::sort(mRanked.begin(), mRanked.end());
        mRankOf.resize(tile.size());
        for (std::size_t rank = 0; rank < mRanked.size(); ++rank) {
            mRankOf[mRanked[rank].second] = static_cast<uint32_t>(rank);
        }
        for (std::size_t r = 0; r < mRowCount; ++r) {
            std::array<uint32_t, PixelKnnTable::kMaxK> row{};
            for (std::size_t w = 0, j = 0; w < mWords; ++w) {
                for (uint64_t bits = mRows[r * mWords + w]; bits != 0; bits &= bits - 1) {
                    row[j++] = static_cast<uint32_t>(64 * w + std::countr_zero(bits));
                }
            }
            if (mRanked.size() <= 64) {
                uint64_t ranks = 0;
                for (uint32_t j = 0; j < mK; ++j) {
                    ranks |= uint64_t{1} << mRankOf[row[j]];
                }
                for (; ranks != 0; ranks &= ranks - 1) {
                    band.slots.push_back(mSlotOf[mRanked[std::countr_zero(ranks)].second]);
                }
            } else {
                std::array<uint32_t, PixelKnnTable::kMaxK> ranks{};
                for (uint32_t j = 0; j < mK; ++j) {
                    ranks[j] = mRankOf[row[j]];
                }
                std::sort(ranks.begin(), ranks.begin() + mK);
                for (uint32_t j = 0; j < mK; ++j) {
                    band.slots.push_back(mSlotOf[mRanked[ranks[j]].second]);
                }
            }
            band.slots.insert(band.slots.end(), mSlotsPerRow - mK, uint16_t{0});
        }
    }

private:
    uint32_t mK, mSlotsPerRow;
    std::size_t mWords = 1, mRowCount = 0;
    std::vector<uint64_t> mRows, mSet; // rows' bit sets, mWords each; the one being added
    std::vector<uint32_t> mRankOf;
    std::vector<uint16_t> mSlotOf;
    std::vector<Candidate> mRanked; // used candidates: (distance^2 from the centre, place)
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
        std::vector<uint32_t> tile, previous;
        std::vector<float> d2, kth;
        Block tileBlock, block;
        BlockSearch search(k);
        std::array<uint32_t, kMaxK> nearest{};
        const uint32_t y0 = band * kTile, y1 = std::min(mHeight, y0 + kTile);
        for (uint32_t t = 0; t < tx; ++t) {
            const uint32_t x0 = t * kTile, x1 = std::min(mWidth, x0 + kTile);
            previous.swap(tile);
            blockCandidates(grids, pts, x0, y0, x1, y1, k, previous, scratch, tile);
            encoder.begin(tile.size());
            // The tile's candidates' positions side by side, read once per quarter.
            tileBlock.x.clear();
            tileBlock.y.clear();
            for (const uint32_t i : tile) {
                tileBlock.x.push_back(pts[i].x);
                tileBlock.y.push_back(pts[i].y);
            }
            // Quarters, each with its own candidates: a bound from nearer its pixels admits
            // fewer points than the tile's.
            constexpr uint32_t side = kTile / 2;
            for (uint32_t qy = y0; qy < y1; qy += side) {
                for (uint32_t qx = x0; qx < x1; qx += side) {
                    const uint32_t qx1 = std::min(x1, qx + side), qy1 = std::min(y1, qy + side);
                    narrow(tileBlock, qx, qy, qx1, qy1, k, d2, kth, block);
                    search.begin(block);
                    uint8_t row = 0;
                    for (uint32_t y = qy; y < qy1; ++y) {
                        for (uint32_t x = qx; x < qx1; ++x) {
                            if (search.search(static_cast<float>(x) + 0.5f,
                                              static_cast<float>(y) + 0.5f)) {
                                search.nearest(nearest.data());
                                row = encoder.add(nearest.data());
                            }
                            mPixelRows[static_cast<std::size_t>(y) * mWidth + x] = row;
                        }
                    }
                }
            }
            encoder.finish(bands[band], tile, pts, 0.5f * static_cast<float>(x0 + x1),
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

std::vector<uint32_t> PixelKnnTable::flatRows(uint32_t y0, uint32_t y1) const {
    const uint32_t perRow = slotsPerRow();
    std::vector<uint32_t> rows(static_cast<std::size_t>(mWidth) * (y1 - y0) * perRow, 0u);
    detail::parallelFor(y1 - y0, [&](uint32_t dy) {
        for (uint32_t x = 0; x < mWidth; ++x) {
            const std::size_t pixel = static_cast<std::size_t>(dy) * mWidth + x;
            decode(x, y0 + dy, std::span(rows).subspan(pixel * perRow, mK));
        }
    });
    return rows;
}

KnnLayout knnLayoutFor(uint32_t canvasWidth, uint32_t canvasHeight, uint32_t k,
                       const KnnDeviceLimits& limits) {
    const uint64_t texels = uint64_t{canvasWidth} * canvasHeight * ((k + 3) / 4);
    const bool fits =
        texels <= limits.maxTexelBufferElements && texels * 16 <= limits.deviceLocalHeapBytes / 3;
    return fits ? KnnLayout::Flat : KnnLayout::Compact;
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
