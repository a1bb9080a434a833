#pragma once
// A point set and its neighbour index on the GPU, as uniform texel buffers: points (x, y, p),
// the nearest point per canvas pixel, and the stored neighbours per point; beside them, on the
// CPU, the set's chunks that point_sample picks from each frame. The index (nearest point and
// neighbours) can stay on the CPU until a pass reads it: Modified Shepard through the k-NN table
// never does, and for a 3840x3744 eye it is 328 MB of the method's memory.
#include <cstdint>
#include <string_view>

#include "foveation/neighbour_index.hpp"
#include "foveation/pixel_knn_table.hpp"
#include "foveation/point_chunks.hpp"
#include "foveation/point_set.hpp"
#include "foveation/rbf_inverse.hpp"
#include "foveation/rbf_pixel_weights.hpp"
#include "vk/resources.hpp"

namespace gt::foveation {

class GpuPointSet {
public:
    enum class Index { Upload, OnDemand };
    GpuPointSet(vk::Context& ctx, const PointSet& set, const NeighbourIndex& index,
                Index upload = Index::Upload);

    // Uploads `index` (the one the set was made with) where it is not on the GPU yet.
    void uploadIndex(vk::Context& ctx, const NeighbourIndex& index);
    [[nodiscard]] bool hasIndex() const noexcept { return mNearestView.handle() != VK_NULL_HANDLE; }
    // Throws std::logic_error naming `reader` where the index is not on the GPU.
    void requireIndex(std::string_view reader) const;

    [[nodiscard]] VkBufferView points() const noexcept { return mPointsView.handle(); }
    // Without the index on the GPU, a one-texel stand-in of the same format: for the bindings
    // of shader variants that never read it (passes check hasIndex() where theirs do).
    [[nodiscard]] VkBufferView nearest() const noexcept { return indexOr(mNearestView); }
    [[nodiscard]] VkBufferView neighbours() const noexcept { return indexOr(mNeighboursView); }
    [[nodiscard]] uint32_t count() const noexcept { return mCount; }
    [[nodiscard]] uint32_t storedNeighbours() const noexcept { return mK; }
    [[nodiscard]] uint32_t canvasWidth() const noexcept { return mCanvasW; }
    [[nodiscard]] uint32_t canvasHeight() const noexcept { return mCanvasH; }
    [[nodiscard]] uint32_t displayWidth() const noexcept { return mDisplayW; }
    [[nodiscard]] uint32_t displayHeight() const noexcept { return mDisplayH; }
    [[nodiscard]] const PointChunks& chunks() const noexcept { return mChunks; }
    // NeighbourIndex::coveringRadius of the set, in canvas pixels.
    [[nodiscard]] float coveringRadius() const noexcept { return mCoveringRadius; }

private:
    [[nodiscard]] VkBufferView indexOr(const vk::BufferView& view) const noexcept {
        return hasIndex() ? view.handle() : mStandInView.handle();
    }

    PointChunks mChunks;
    vk::Buffer mPoints, mNearest, mNeighbours, mStandIn;
    vk::BufferView mPointsView, mNearestView, mNeighboursView, mStandInView;
    uint32_t mCount, mK, mCanvasW, mCanvasH, mDisplayW, mDisplayH;
    float mCoveringRadius;
};

// The precomputed RBF inverses on the GPU: per point, ceil(k^2 / 4) RGBA32F texels holding the
// k x k inverse row-major (texel buffers reach 128 M texels on lavapipe; storage buffers only
// 128 MiB).
class GpuRbfInverse {
public:
    GpuRbfInverse(vk::Context& ctx, const RbfInverse& inverse);
    [[nodiscard]] VkBufferView view() const noexcept { return mView.handle(); }
    [[nodiscard]] uint32_t k() const noexcept { return mK; }
    [[nodiscard]] uint32_t texelsPerPoint() const noexcept { return mStride; }
    [[nodiscard]] RbfKernelType kernel() const noexcept { return mKernel; }
    [[nodiscard]] float shape() const noexcept { return mShape; }

private:
    vk::Buffer mBuffer;
    vk::BufferView mView;
    uint32_t mK, mStride = 0;
    RbfKernelType mKernel;
    float mShape;
};

// The device's limits on the flat k-NN table (knnLayoutFor, pixel_knn_table.hpp).
[[nodiscard]] KnnDeviceLimits knnDeviceLimits(const vk::Context& ctx);

// The thesis's per-canvas-pixel k-NN table on the GPU, flat where it fits the device and compact
// beyond (knnLayoutFor). Flat: per canvas pixel texelsPerRow() RGBA32UI texels of its k nearest,
// nearest first, in slots(). Compact (pixel_knn_table.hpp): per tile (candidate base, row base)
// as RG32UI, the candidates as R32UI, the rows' slots as RGBA8UI or RGBA16UI (four slots a
// texel), the pixels' rows as R8UI; flat, those three views are slots()'s (never read).
class GpuPixelKnnTable {
public:
    GpuPixelKnnTable(vk::Context& ctx, const PixelKnnTable& table);
    GpuPixelKnnTable(vk::Context& ctx, const PixelKnnTable& table, KnnLayout layout);
    [[nodiscard]] KnnLayout layout() const noexcept { return mLayout; }
    [[nodiscard]] VkBufferView tiles() const noexcept { return flatOr(mTilesView); }
    [[nodiscard]] VkBufferView candidates() const noexcept { return flatOr(mCandidatesView); }
    [[nodiscard]] VkBufferView slots() const noexcept { return mSlotsView.handle(); }
    [[nodiscard]] VkBufferView pixelRows() const noexcept { return flatOr(mPixelRowsView); }
    [[nodiscard]] uint32_t k() const noexcept { return mK; }
    // Texels per row of slots: per canvas pixel when flat.
    [[nodiscard]] uint32_t texelsPerRow() const noexcept { return mTexelsPerRow; }
    [[nodiscard]] std::size_t bytes() const noexcept { return mBytes; }

private:
    [[nodiscard]] VkBufferView flatOr(const vk::BufferView& view) const noexcept {
        return mLayout == KnnLayout::Flat ? mSlotsView.handle() : view.handle();
    }

    vk::Buffer mTiles, mCandidates, mSlots, mPixelRows;
    vk::BufferView mTilesView, mCandidatesView, mSlotsView, mPixelRowsView;
    KnnLayout mLayout;
    uint32_t mK, mTexelsPerRow;
    std::size_t mBytes = 0;
};

// The per-pixel RBF weights on the GPU, laid out as the k-NN table they belong to: ceil(k / 4)
// RGBA32F texels per canvas pixel.
class GpuRbfPixelWeights {
public:
    GpuRbfPixelWeights(vk::Context& ctx, const RbfPixelWeights& weights);
    [[nodiscard]] VkBufferView view() const noexcept { return mView.handle(); }
    [[nodiscard]] uint32_t k() const noexcept { return mK; }
    [[nodiscard]] RbfKernelType kernel() const noexcept { return mKernel; }
    [[nodiscard]] float shape() const noexcept { return mShape; }

private:
    vk::Buffer mBuffer;
    vk::BufferView mView;
    uint32_t mK;
    RbfKernelType mKernel;
    float mShape;
};

} // namespace gt::foveation
