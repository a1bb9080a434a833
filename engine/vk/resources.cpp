#include "vk/resources.hpp"

#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "vk/context.hpp"

namespace gt::vk {

Buffer::Buffer(Context& ctx, const BufferDesc& desc) : mCtx(&ctx), mSize(desc.size) {
    if (desc.size == 0) throw Error("buffer '" + desc.name + "' has size 0");
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = desc.size;
    info.usage = desc.usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    GT_VK_CHECK(vkCreateBuffer(ctx.device(), &info, nullptr, &mBuffer));
    try {
        VkMemoryRequirements req{};
        vkGetBufferMemoryRequirements(ctx.device(), mBuffer, &req);
        mAllocation = ctx.allocator().allocate(req, desc.memory);
        GT_VK_CHECK(
            vkBindBufferMemory(ctx.device(), mBuffer, mAllocation.memory, mAllocation.offset));
    } catch (const VulkanError& e) {
        reset();
        char size[32];
        std::snprintf(size, sizeof size, "%.1f GiB", static_cast<double>(desc.size) / (1u << 30));
        const std::string what = "allocating the buffer '" + desc.name + "' (" + size + ")";
        throw VulkanError(e.result(), what.c_str(), __FILE__, __LINE__);
    } catch (...) {
        reset();
        throw;
    }
    if (!desc.name.empty()) {
        ctx.setName(VK_OBJECT_TYPE_BUFFER, reinterpret_cast<uint64_t>(mBuffer), desc.name);
    }
}

Buffer::~Buffer() {
    reset();
}

void Buffer::reset() noexcept {
    if (!mCtx) return;
    if (mBuffer != VK_NULL_HANDLE) vkDestroyBuffer(mCtx->device(), mBuffer, nullptr);
    mCtx->allocator().free(mAllocation);
    mBuffer = VK_NULL_HANDLE;
    mAllocation = {};
    mCtx = nullptr;
}

Buffer::Buffer(Buffer&& o) noexcept
    : mCtx(std::exchange(o.mCtx, nullptr)), mBuffer(std::exchange(o.mBuffer, VK_NULL_HANDLE)),
      mSize(std::exchange(o.mSize, 0)), mAllocation(std::exchange(o.mAllocation, {})) {}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        reset();
        mCtx = std::exchange(o.mCtx, nullptr);
        mBuffer = std::exchange(o.mBuffer, VK_NULL_HANDLE);
        mSize = std::exchange(o.mSize, 0);
        mAllocation = std::exchange(o.mAllocation, {});
    }
    return *this;
}

void Buffer::upload(std::span<const std::byte> bytes, VkDeviceSize offset) {
    if (bytes.empty()) return;
    if (offset + bytes.size() > mSize) throw Error("buffer upload out of range");
    if (mAllocation.mapped) {
        std::memcpy(mAllocation.mapped + offset, bytes.data(), bytes.size());
        if (!mAllocation.coherent) {
            VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
            range.memory = mAllocation.memory;
            range.offset = 0;
            range.size = VK_WHOLE_SIZE;
            GT_VK_CHECK(vkFlushMappedMemoryRanges(mCtx->device(), 1, &range));
        }
        return;
    }
    Buffer staging(
        *mCtx, {bytes.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::Upload, "staging"});
    staging.upload(bytes);
    mCtx->submitAndWait([&](VkCommandBuffer cmd) {
        VkBufferCopy region{0, offset, bytes.size()};
        vkCmdCopyBuffer(cmd, staging.handle(), mBuffer, 1, &region);
    });
}

void Buffer::download(std::span<std::byte> out, VkDeviceSize offset) const {
    if (!mAllocation.mapped) throw Error("buffer download from memory that is not host-visible");
    if (offset + out.size() > mSize) throw Error("buffer download out of range");
    if (!mAllocation.coherent) {
        VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
        range.memory = mAllocation.memory;
        range.size = VK_WHOLE_SIZE;
        GT_VK_CHECK(vkInvalidateMappedMemoryRanges(mCtx->device(), 1, &range));
    }
    std::memcpy(out.data(), mAllocation.mapped + offset, out.size());
}

uint32_t bytesPerPixel(VkFormat format) {
    switch (format) {
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_B8G8R8A8_UNORM:
    case VK_FORMAT_B8G8R8A8_SRGB:
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_R32_UINT:
        return 4;
    case VK_FORMAT_R16G16B16A16_SFLOAT:
    case VK_FORMAT_R32G32_SFLOAT:
        return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT:
        return 16;
    default:
        throw Error("unsupported image format " + std::to_string(format));
    }
}

namespace {
// "the 16384x16384 image 'hdr' (1.0 GiB)": what an allocation was for, in its failure's message.
std::string imageWhat(const ImageDesc& desc, VkDeviceSize bytes) {
    char size[32];
    std::snprintf(size, sizeof size, "%.1f GiB", static_cast<double>(bytes) / (1u << 30));
    return "the " + std::to_string(desc.width) + "x" + std::to_string(desc.height) + " image '" +
           desc.name + "' (" + size + ")";
}
} // namespace

Image::Image(Context& ctx, const ImageDesc& desc) : mCtx(&ctx), mDesc(desc) {
    if (desc.width == 0 || desc.height == 0) {
        throw Error("image '" + desc.name + "' has zero size");
    }
    // Larger than the device's largest image is invalid usage, not an error code: refused here.
    const uint32_t maxSide = ctx.properties().limits.maxImageDimension2D;
    if (desc.width > maxSide || desc.height > maxSide) {
        throw Error("image '" + desc.name + "' of " + std::to_string(desc.width) + "x" +
                    std::to_string(desc.height) + " pixels is larger than the device allows (" +
                    std::to_string(maxSide) + " pixels a side)");
    }
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = desc.format;
    info.extent = {desc.width, desc.height, 1};
    info.mipLevels = 1;
    info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = desc.usage;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    GT_VK_CHECK(vkCreateImage(ctx.device(), &info, nullptr, &mImage));
    VkMemoryRequirements req{};
    try {
        vkGetImageMemoryRequirements(ctx.device(), mImage, &req);
        mAllocation = ctx.allocator().allocate(req, MemoryUsage::GpuOnly);
        GT_VK_CHECK(
            vkBindImageMemory(ctx.device(), mImage, mAllocation.memory, mAllocation.offset));
        // A view only where a shader or an attachment can use one (a copy or blit target, such
        // as the side-by-side composite, may not have one).
        constexpr VkImageUsageFlags viewable = VK_IMAGE_USAGE_SAMPLED_BIT |
                                               VK_IMAGE_USAGE_STORAGE_BIT |
                                               VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
        if ((desc.usage & viewable) != 0) {
            VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
            view.image = mImage;
            view.viewType = VK_IMAGE_VIEW_TYPE_2D;
            view.format = desc.format;
            view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
            GT_VK_CHECK(vkCreateImageView(ctx.device(), &view, nullptr, &mView));
        }
    } catch (const VulkanError& e) {
        reset();
        // The same result, said with what was being allocated, so the app can tell the user
        // which image did not fit.
        const std::string what = "allocating " + imageWhat(desc, req.size);
        throw VulkanError(e.result(), what.c_str(), __FILE__, __LINE__);
    } catch (...) {
        reset();
        throw;
    }
    if (!desc.name.empty()) {
        ctx.setName(VK_OBJECT_TYPE_IMAGE, reinterpret_cast<uint64_t>(mImage), desc.name);
    }
}

Image::~Image() {
    reset();
}

void Image::reset() noexcept {
    if (!mCtx) return;
    if (mView != VK_NULL_HANDLE) vkDestroyImageView(mCtx->device(), mView, nullptr);
    if (mImage != VK_NULL_HANDLE) vkDestroyImage(mCtx->device(), mImage, nullptr);
    mCtx->allocator().free(mAllocation);
    mView = VK_NULL_HANDLE;
    mImage = VK_NULL_HANDLE;
    mAllocation = {};
    mCtx = nullptr;
}

Image::Image(Image&& o) noexcept
    : mCtx(std::exchange(o.mCtx, nullptr)), mImage(std::exchange(o.mImage, VK_NULL_HANDLE)),
      mView(std::exchange(o.mView, VK_NULL_HANDLE)), mDesc(std::move(o.mDesc)),
      mAllocation(std::exchange(o.mAllocation, {})) {}

Image& Image::operator=(Image&& o) noexcept {
    if (this != &o) {
        reset();
        mCtx = std::exchange(o.mCtx, nullptr);
        mImage = std::exchange(o.mImage, VK_NULL_HANDLE);
        mView = std::exchange(o.mView, VK_NULL_HANDLE);
        mDesc = std::move(o.mDesc);
        mAllocation = std::exchange(o.mAllocation, {});
    }
    return *this;
}

BufferView::BufferView(Context& ctx, const Buffer& buffer, VkFormat format)
    : mDevice(ctx.device()) {
    VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
    info.buffer = buffer.handle();
    info.format = format;
    info.offset = 0;
    info.range = VK_WHOLE_SIZE;
    GT_VK_CHECK(vkCreateBufferView(mDevice, &info, nullptr, &mView));
}

BufferView::~BufferView() {
    if (mView != VK_NULL_HANDLE) vkDestroyBufferView(mDevice, mView, nullptr);
}

BufferView::BufferView(BufferView&& o) noexcept
    : mDevice(o.mDevice), mView(std::exchange(o.mView, VK_NULL_HANDLE)) {}

BufferView& BufferView::operator=(BufferView&& o) noexcept {
    if (this != &o) {
        if (mView != VK_NULL_HANDLE) vkDestroyBufferView(mDevice, mView, nullptr);
        mDevice = o.mDevice;
        mView = std::exchange(o.mView, VK_NULL_HANDLE);
    }
    return *this;
}

} // namespace gt::vk
