#include "foveation/gpu_point_set.hpp"

#include <algorithm>

#include <glm/glm.hpp>

namespace gt::foveation {

GpuPointSet::GpuPointSet(vk::Context& ctx, const PointSet& set, const NeighbourIndex& index)
    : mCount(static_cast<uint32_t>(set.points().size())), mK(index.k()),
      mCanvasW(set.canvasWidth()), mCanvasH(set.canvasHeight()),
      mDisplayW(set.params().display.width), mDisplayH(set.params().display.height) {
    std::vector<glm::vec4> pts;
    pts.reserve(set.points().size());
    for (const Point& p : set.points())
        pts.emplace_back(p.x, p.y, p.spacing, 0.0f);
    auto make = [&](vk::Buffer& buffer, const void* data, std::size_t bytes, const char* name) {
        buffer = vk::Buffer(
            ctx, {bytes, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT, vk::MemoryUsage::GpuOnly, name});
        buffer.upload(std::span(static_cast<const std::byte*>(data), bytes));
    };
    make(mPoints, pts.data(), pts.size() * sizeof(glm::vec4), "pointset.points");
    make(mNearest, index.nearest().data(), index.nearest().size() * 4, "pointset.nearest");
    make(mNeighbours, index.neighbours().data(), index.neighbours().size() * 4,
         "pointset.neighbours");
    mPointsView = vk::BufferView(ctx, mPoints, VK_FORMAT_R32G32B32A32_SFLOAT);
    mNearestView = vk::BufferView(ctx, mNearest, VK_FORMAT_R32_UINT);
    mNeighboursView = vk::BufferView(ctx, mNeighbours, VK_FORMAT_R32_UINT);
}

GpuRbfInverse::GpuRbfInverse(vk::Context& ctx, const RbfInverse& inverse)
    : mK(inverse.k), mStride((inverse.k * inverse.k + 3) / 4), mKernel(inverse.kernel),
      mShape(inverse.shape) {
    const std::size_t points = inverse.inverse.size() / (static_cast<std::size_t>(mK) * mK);
    const std::size_t bytes = points * mStride * 16;
    mBuffer = vk::Buffer(ctx, {bytes, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT,
                               vk::MemoryUsage::GpuOnly, "rbf.inverse"});
    std::vector<float> padded(points * mStride * 4, 0.0f);
    for (std::size_t q = 0; q < points; ++q) {
        std::copy_n(&inverse.inverse[q * mK * mK], mK * mK, &padded[q * mStride * 4]);
    }
    mBuffer.upload(std::as_bytes(std::span(padded)));
    mView = vk::BufferView(ctx, mBuffer, VK_FORMAT_R32G32B32A32_SFLOAT);
}

GpuPixelKnnTable::GpuPixelKnnTable(vk::Context& ctx, const PixelKnnTable& table)
    : mK(table.k()), mStride((table.k() + 3) / 4) {
    const std::size_t pixels = static_cast<std::size_t>(table.canvasWidth()) * table.canvasHeight();
    const std::size_t bytes = pixels * mStride * 16;
    mBuffer = vk::Buffer(ctx, {bytes, VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT,
                               vk::MemoryUsage::GpuOnly, "pointset.knn_table"});
    if (mStride * 4 == mK) {
        mBuffer.upload(std::as_bytes(std::span(table.indices())));
    } else {
        std::vector<uint32_t> padded(pixels * mStride * 4, 0u);
        for (std::size_t p = 0; p < pixels; ++p)
            std::copy_n(&table.indices()[p * mK], mK, &padded[p * mStride * 4]);
        mBuffer.upload(std::as_bytes(std::span(padded)));
    }
    mView = vk::BufferView(ctx, mBuffer, VK_FORMAT_R32G32B32A32_UINT);
}

} // namespace gt::foveation
