#pragma once
// The thesis's k-nearest-neighbour table (thesis, 4.1 and 4.3): for every pixel of the
// 2W x 2H canvas, the indices of its k nearest points, nearest first. Shifting the lookup by the
// gaze gives every screen pixel its neighbours with one fetch per neighbour and no search.
// It is exact (ties on distance go to the lower point index) and large: 2W x 2H x k x 4 B,
// 590 MB for the fove profile at k = 20, against 75.6 MB for NeighbourIndex, which answers
// the same question from the nearest point's neighbour list (see neighbour_index.hpp).
#include <cstdint>
#include <vector>

#include "foveation/neighbour_index.hpp"
#include "foveation/point_set.hpp"

namespace gt::foveation {

class PixelKnnTable {
public:
    // `index` bounds each search (its candidates give an upper bound on the k-th distance).
    PixelKnnTable(const PointSet& set, const NeighbourIndex& index, uint32_t k);

    [[nodiscard]] uint32_t k() const noexcept { return mK; }
    [[nodiscard]] uint32_t canvasWidth() const noexcept { return mWidth; }
    [[nodiscard]] uint32_t canvasHeight() const noexcept { return mHeight; }
    // Row-major over the canvas, k indices per pixel.
    [[nodiscard]] const std::vector<uint32_t>& indices() const noexcept { return mIndices; }
    [[nodiscard]] std::size_t bytes() const noexcept { return mIndices.size() * sizeof(uint32_t); }
    [[nodiscard]] double buildSeconds() const noexcept { return mSeconds; }

private:
    uint32_t mK, mWidth, mHeight;
    std::vector<uint32_t> mIndices;
    double mSeconds = 0.0;
};

// The k nearest points to (x, y) by testing every point (for tests), in the table's order.
[[nodiscard]] std::vector<uint32_t> bruteForceKnn(const PointSet& set, float x, float y,
                                                  uint32_t k);

} // namespace gt::foveation
