#pragma once
// The thesis's k-nearest-neighbour table (thesis, 4.1 and 4.3): for every pixel of the
// 2W x 2H canvas, the indices of its k nearest points, nearest first. Shifting the lookup by the
// gaze gives every screen pixel its neighbours with a few fetches and no search. It is exact
// (ties on distance go to the lower point index).
//
// Stored as the interpolation reads it and no more. Stored flat (k x 4 B per canvas pixel) it
// grows with the display: 2.3 GB at k = 10 for a 3840x3744 eye. But neighbouring pixels mostly
// share their k nearest as a set (the order changes far more often than the set), and the
// order is recomputed from the points where it is read. So the canvas is cut into
// kTile x kTile tiles, and each tile keeps
//   - its candidates: the points that are among some pixel's k nearest, by index,
//   - its rows: the distinct sets of k nearest of its pixels, each k slots into the
//     candidates, nearest to the tile's centre first, so that a pixel reads its set nearly in
//     its own order and sorts it in few steps (one byte per slot where every tile has at most 256
//     candidates, else two), and
//   - per pixel, one byte: which of the tile's rows is the pixel's.
// A pixel's set is candidates[tile.base + slot[tile.row + row(pixel)][j]], j < k; sorted by
// (float squared distance from the pixel centre, index) it is the flat table's row.
#include <cstdint>
#include <span>
#include <vector>

#include "foveation/point_set.hpp"

namespace gt::foveation {

class NeighbourIndex;

class PixelKnnTable {
public:
    static constexpr uint32_t kTile = 8; // pixels per tile side: at most 64 rows per tile
    static constexpr uint32_t kMaxK = 20;

    // The k nearest points of every canvas pixel (k = 1..kMaxK), built over row bands of tiles
    // on every core; the result does not depend on the number of threads. `set` must outlive
    // the table (decode reads its points).
    PixelKnnTable(const PointSet& set, uint32_t k);
    // As above, for a k the neighbour index's lists can also serve (k <= index.k() + 1).
    PixelKnnTable(const PointSet& set, const NeighbourIndex& index, uint32_t k);

    [[nodiscard]] uint32_t k() const noexcept { return mK; }
    [[nodiscard]] uint32_t canvasWidth() const noexcept { return mWidth; }
    [[nodiscard]] uint32_t canvasHeight() const noexcept { return mHeight; }
    [[nodiscard]] uint32_t tilesX() const noexcept { return (mWidth + kTile - 1) / kTile; }
    [[nodiscard]] uint32_t tilesY() const noexcept { return (mHeight + kTile - 1) / kTile; }

    // The j-th (j < k) of canvas pixel (x, y)'s k nearest points, in the order stored (nearest
    // to the centre of the pixel's 8x8 tile first); for k = 1 its nearest point.
    [[nodiscard]] uint32_t entry(uint32_t x, uint32_t y, uint32_t j) const noexcept {
        const std::size_t tile = static_cast<std::size_t>(y / kTile) * tilesX() + x / kTile;
        const std::size_t row =
            mTiles[2 * tile + 1] + mPixelRows[static_cast<std::size_t>(y) * mWidth + x];
        return mCandidates[mTiles[2 * tile] + slot(row * slotsPerRow() + j)];
    }
    // Canvas pixel (x, y)'s k nearest, nearest first (ties to the lower index), into `out`
    // (k entries): the flat table's row.
    void decode(uint32_t x, uint32_t y, std::span<uint32_t> out) const;
    // Every canvas pixel's row decoded (row-major), slotsPerRow() entries each: the k nearest,
    // nearest first, then zeros; of canvas rows [y0, y1) only, for a table uploaded in parts.
    // Decoded on every core; the same for any number of them.
    [[nodiscard]] std::vector<uint32_t> flatRows() const { return flatRows(0, mHeight); }
    [[nodiscard]] std::vector<uint32_t> flatRows(uint32_t y0, uint32_t y1) const;

    // The layout, as the GPU reads it (gpu_point_set.hpp): per tile (candidate base, row base);
    // the candidates; the rows' slots, slotsPerRow() of slotBytes() each (little-endian), the
    // unused ones 0; per canvas pixel (row-major) its row in its tile.
    [[nodiscard]] const std::vector<uint32_t>& tiles() const noexcept { return mTiles; }
    [[nodiscard]] const std::vector<uint32_t>& candidates() const noexcept { return mCandidates; }
    [[nodiscard]] const std::vector<uint8_t>& slots() const noexcept { return mSlots; }
    [[nodiscard]] const std::vector<uint8_t>& pixelRows() const noexcept { return mPixelRows; }
    [[nodiscard]] uint32_t slotBytes() const noexcept { return mSlotBytes; }
    [[nodiscard]] uint32_t slotsPerRow() const noexcept { return (mK + 3) / 4 * 4; }
    [[nodiscard]] std::size_t rows() const noexcept {
        return mSlots.size() / (static_cast<std::size_t>(slotsPerRow()) * mSlotBytes);
    }

    [[nodiscard]] std::size_t bytes() const noexcept {
        return (mTiles.size() + mCandidates.size()) * sizeof(uint32_t) + mSlots.size() +
               mPixelRows.size();
    }
    // What the flat table (k indices of 4 B per canvas pixel) would take.
    [[nodiscard]] std::size_t flatBytes() const noexcept {
        return static_cast<std::size_t>(mWidth) * mHeight * mK * sizeof(uint32_t);
    }
    [[nodiscard]] double buildSeconds() const noexcept { return mSeconds; }

private:
    static uint32_t checkedK(const NeighbourIndex& index, uint32_t k);
    [[nodiscard]] uint32_t slot(std::size_t i) const noexcept {
        return mSlotBytes == 1 ? mSlots[i] : mSlots[2 * i] | (uint32_t{mSlots[2 * i + 1]} << 8);
    }

    const PointSet* mSet;
    uint32_t mK, mWidth, mHeight, mSlotBytes = 1;
    std::vector<uint32_t> mTiles, mCandidates;
    std::vector<uint8_t> mSlots, mPixelRows;
    double mSeconds = 0.0;
};

// How the table is stored on the GPU (gpu_point_set.hpp). Flat: flatRows(), as the interpolation
// reads them, one fetch per four neighbours and nothing to decode; compact: the layout above,
// a seventh of the bytes at k = 10 and more fetches per pixel (the interpolation reads Modified
// Shepard's neighbours 1.4-2.2 times slower through it on lavapipe).
enum class KnnLayout { Flat, Compact };

// What bounds the flat table on a device.
struct KnnDeviceLimits {
    uint64_t deviceLocalHeapBytes = 0;   // the largest device-local memory heap
    uint64_t maxTexelBufferElements = 0; // texels one texel buffer may hold
};

// Flat where it fits: its texels (ceil(k / 4) RGBA32UI per canvas pixel) in one texel buffer,
// and its bytes at most a third of the device-local heap, which leaves the rest to the frame's
// images, the set and a second eye. Compact beyond. On lavapipe (2 GiB, 128 M texels) the fove
// eye's table is flat up to k = 20 (590 MB) and a 3840x3744 eye's compact from k = 1.
[[nodiscard]] KnnLayout knnLayoutFor(uint32_t canvasWidth, uint32_t canvasHeight, uint32_t k,
                                     const KnnDeviceLimits& limits);

// The k nearest points to (x, y) by testing every point (for tests), in the table's order.
[[nodiscard]] std::vector<uint32_t> bruteForceKnn(const PointSet& set, float x, float y,
                                                  uint32_t k);

} // namespace gt::foveation
