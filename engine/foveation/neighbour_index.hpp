#pragma once
// k-nearest-neighbour lookup for scattered interpolation (thesis 4.1/4.3). The thesis stores,
// for every canvas pixel, the indices of its 20 nearest points: 2W x 2H x 20 x 4 B = 590 MB
// for the fove profile, more than a quarter of lavapipe's heap and beyond one storage buffer
// (docs/lavapipe.md). gazetrace stores instead
//   - nearest: for every canvas pixel, its nearest point (the k = 1 table, pixel_knn_table.hpp:
//     about a byte per canvas pixel; 2W x 2H x 4 B = 29.5 MB for fove on the GPU), and
//   - neighbours: for every point, its kMax nearest other points (N x kMax x 4 B, 46 MB),
// and a pixel takes its k nearest among {nearest point} + that point's neighbour list. Because
// the set only shifts with the gaze (by whole pixels), both tables are built once per set.
// The nearest neighbour is exact; for k > 1 the candidates are the true k nearest whenever
// those lie within the nearest point's own k-neighbourhood, which holds for all but pixels
// near the edge of a neighbourhood (tests measure the agreement).
#include <cstdint>
#include <vector>

#include "foveation/pixel_knn_table.hpp"
#include "foveation/point_set.hpp"

namespace gt::foveation {

class NeighbourIndex {
public:
    static constexpr uint32_t kMaxNeighbours = 20;

    NeighbourIndex(const PointSet& set, uint32_t k = kMaxNeighbours);

    [[nodiscard]] uint32_t k() const noexcept { return mK; }
    [[nodiscard]] uint32_t canvasWidth() const noexcept { return mWidth; }
    [[nodiscard]] uint32_t canvasHeight() const noexcept { return mHeight; }
    // The nearest point of every canvas pixel.
    [[nodiscard]] const PixelKnnTable& nearest() const noexcept { return mNearest; }
    // The same, one index per canvas pixel (row-major), as the GPU reads it.
    [[nodiscard]] std::vector<uint32_t> nearestPerPixel() const;
    [[nodiscard]] const std::vector<uint32_t>& neighbours() const noexcept { return mNeighbours; }
    // The farthest any canvas pixel's centre lies from its nearest point: the set's covering
    // radius at pixel resolution. A screen pixel's nearest point lies within it, so where it is
    // at most the sampling margin, that point is always one that point_sample traced.
    [[nodiscard]] float coveringRadius() const;
    [[nodiscard]] std::size_t bytes() const noexcept {
        return mNearest.bytes() + mNeighbours.size() * sizeof(uint32_t);
    }
    [[nodiscard]] double buildSeconds() const noexcept { return mSeconds; }
    // Bytes the thesis's per-pixel table would take for this set and k.
    [[nodiscard]] std::size_t perPixelTableBytes(uint32_t k) const noexcept {
        return static_cast<std::size_t>(mWidth) * mHeight * k * sizeof(uint32_t);
    }

    // The k nearest points to canvas position (x, y) by this index's rule, nearest first.
    [[nodiscard]] std::vector<uint32_t> query(float x, float y, uint32_t k) const;

private:
    const PointSet* mSet;
    uint32_t mK, mWidth, mHeight;
    PixelKnnTable mNearest;
    std::vector<uint32_t> mNeighbours;
    double mSeconds = 0.0;
};

} // namespace gt::foveation
