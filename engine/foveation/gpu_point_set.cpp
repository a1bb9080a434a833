#include "foveation/gpu_point_set.hpp"

#include <algorithm>
#include <array>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "vk/context.hpp"

namespace gt::foveation {

namespace {

void uploadTexels(vk::Context& ctx, vk::Buffer& buffer, const void* data, std::size_t bytes,
                  const char* name) {
    buffer = vk::Buffer(
        ctx, {bytes, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT, vk::MemoryUsage::GpuOnly, name});
    buffer.upload(std::span(static_cast<const std::byte*>(data), bytes));
}

} // namespace

GpuPointSet::GpuPointSet(vk::Context& ctx, const PointSet& set, const NeighbourIndex& index,
                         Index upload)
    : mChunks(set), mCount(static_cast<uint32_t>(set.points().size())), mK(index.k()),
      mCanvasW(set.canvasWidth()), mCanvasH(set.canvasHeight()),
      mDisplayW(set.params().display.width), mDisplayH(set.params().display.height),
      mCoveringRadius(index.coveringRadius()) {
    std::vector<glm::vec4> pts;
    pts.reserve(set.points().size());
    for (const Point& p : set.points()) {
        pts.emplace_back(p.x, p.y, p.spacing, 0.0f);
    }
    uploadTexels(ctx, mPoints, pts.data(), pts.size() * sizeof(glm::vec4), "pointset.points");
    mPointsView = vk::BufferView(ctx, mPoints, VK_FORMAT_R32G32B32A32_SFLOAT);
    const std::array<uint32_t, 4> none{};
    uploadTexels(ctx, mStandIn, none.data(), sizeof none, "pointset.index_stand_in");
    mStandInView = vk::BufferView(ctx, mStandIn, VK_FORMAT_R32_UINT);
    if (upload == Index::Upload) {
        uploadIndex(ctx, index);
    }
}

void GpuPointSet::requireIndex(std::string_view reader) const {
    if (!hasIndex()) {
        throw std::logic_error(std::string(reader) +
                               ": the point set's neighbour index is not on the GPU");
    }
}

void GpuPointSet::uploadIndex(vk::Context& ctx, const NeighbourIndex& index) {
    if (hasIndex()) {
        return;
    }
    const std::vector<uint32_t> nearest = index.nearestPerPixel();
    uploadTexels(ctx, mNeighbours, index.neighbours().data(), index.neighbours().size() * 4,
                 "pointset.neighbours");
    mNeighboursView = vk::BufferView(ctx, mNeighbours, VK_FORMAT_R32_UINT);
    // The nearest buffer last: hasIndex() says the whole index is there.
    uploadTexels(ctx, mNearest, nearest.data(), nearest.size() * 4, "pointset.nearest");
    mNearestView = vk::BufferView(ctx, mNearest, VK_FORMAT_R32_UINT);
}

namespace {

// Rows of `rowLength` values, each padded to whole RGBA texels (texel buffers reach 128 M
// texels on lavapipe; storage buffers only 128 MiB), uploaded with a view of `format`.
// Returns the texels per row.
template <typename T>
uint32_t uploadTexelRows(vk::Context& ctx, std::span<const T> values, uint32_t rowLength,
                         VkFormat format, const char* name, vk::Buffer& buffer,
                         vk::BufferView& view) {
    const uint32_t stride = (rowLength + 3) / 4;
    const std::size_t rows = values.size() / rowLength;
    buffer = vk::Buffer(ctx, {rows * stride * 16, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT,
                              vk::MemoryUsage::GpuOnly, name});
    if (stride * 4 == rowLength) {
        buffer.upload(std::as_bytes(values));
    } else {
        std::vector<T> padded(rows * stride * 4, T{});
        for (std::size_t r = 0; r < rows; ++r) {
            std::copy_n(&values[r * rowLength], rowLength, &padded[r * stride * 4]);
        }
        buffer.upload(std::as_bytes(std::span(padded)));
    }
    view = vk::BufferView(ctx, buffer, format);
    return stride;
}

} // namespace

GpuRbfInverse::GpuRbfInverse(vk::Context& ctx, const RbfInverse& inverse)
    : mK(inverse.k), mKernel(inverse.kernel), mShape(inverse.shape) {
    mStride = uploadTexelRows(ctx, std::span<const float>(inverse.inverse), mK * mK,
                              VK_FORMAT_R32G32B32A32_SFLOAT, "rbf.inverse", mBuffer, mView);
}

KnnDeviceLimits knnDeviceLimits(const vk::Context& ctx) {
    VkPhysicalDeviceMemoryProperties memory{};
    vkGetPhysicalDeviceMemoryProperties(ctx.physicalDevice(), &memory);
    KnnDeviceLimits limits;
    for (uint32_t i = 0; i < memory.memoryHeapCount; ++i) {
        if ((memory.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) != 0) {
            limits.deviceLocalHeapBytes =
                std::max<uint64_t>(limits.deviceLocalHeapBytes, memory.memoryHeaps[i].size);
        }
    }
    limits.maxTexelBufferElements = ctx.properties().limits.maxTexelBufferElements;
    return limits;
}

GpuPixelKnnTable::GpuPixelKnnTable(vk::Context& ctx, const PixelKnnTable& table)
    : GpuPixelKnnTable(ctx, table,
                       knnLayoutFor(table.canvasWidth(), table.canvasHeight(), table.k(),
                                    knnDeviceLimits(ctx))) {}

GpuPixelKnnTable::GpuPixelKnnTable(vk::Context& ctx, const PixelKnnTable& table, KnnLayout layout)
    : mLayout(layout), mK(table.k()), mTexelsPerRow(table.slotsPerRow() / 4) {
    auto make = [&](vk::Buffer& buffer, vk::BufferView& view, std::span<const std::byte> bytes,
                    VkFormat format, const char* name) {
        buffer = vk::Buffer(ctx, {bytes.size(), VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT,
                                  vk::MemoryUsage::GpuOnly, name});
        buffer.upload(bytes);
        view = vk::BufferView(ctx, buffer, format);
    };
    if (layout == KnnLayout::Flat) {
        // Decoded and uploaded a band of canvas rows at a time (about 64 MB), so that the host
        // never holds the whole flat table beside the compact one.
        const std::size_t rowBytes = std::size_t{table.canvasWidth()} * table.slotsPerRow() * 4;
        mBytes = rowBytes * table.canvasHeight();
        mSlots = vk::Buffer(ctx, {mBytes, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT,
                                  vk::MemoryUsage::GpuOnly, "pointset.knn_table"});
        const auto band = static_cast<uint32_t>(std::max<std::size_t>(1, (64u << 20) / rowBytes));
        for (uint32_t y = 0; y < table.canvasHeight(); y += band) {
            const std::vector<uint32_t> rows =
                table.flatRows(y, std::min(table.canvasHeight(), y + band));
            mSlots.upload(std::as_bytes(std::span(rows)), y * rowBytes);
        }
        mSlotsView = vk::BufferView(ctx, mSlots, VK_FORMAT_R32G32B32A32_UINT);
        return;
    }
    mBytes = table.bytes();
    make(mTiles, mTilesView, std::as_bytes(std::span(table.tiles())), VK_FORMAT_R32G32_UINT,
         "pointset.knn_tiles");
    make(mCandidates, mCandidatesView, std::as_bytes(std::span(table.candidates())),
         VK_FORMAT_R32_UINT, "pointset.knn_candidates");
    make(mSlots, mSlotsView, std::as_bytes(std::span(table.slots())),
         table.slotBytes() == 1 ? VK_FORMAT_R8G8B8A8_UINT : VK_FORMAT_R16G16B16A16_UINT,
         "pointset.knn_slots");
    make(mPixelRows, mPixelRowsView, std::as_bytes(std::span(table.pixelRows())), VK_FORMAT_R8_UINT,
         "pointset.knn_pixel_rows");
}

GpuRbfPixelWeights::GpuRbfPixelWeights(vk::Context& ctx, const RbfPixelWeights& weights)
    : mK(weights.k()), mKernel(weights.kernel()), mShape(weights.shape()) {
    (void)uploadTexelRows(ctx, std::span<const float>(weights.weights()), mK,
                          VK_FORMAT_R32G32B32A32_SFLOAT, "rbf.pixel_weights", mBuffer, mView);
}

} // namespace gt::foveation
