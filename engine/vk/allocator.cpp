#include "vk/allocator.hpp"

#include <algorithm>

#include "core/error.hpp"

namespace gt::vk {

namespace {
VkDeviceSize alignUp(VkDeviceSize v, VkDeviceSize a) {
    return (v + a - 1) / a * a;
}
} // namespace

Allocator::Allocator(VkPhysicalDevice physicalDevice, VkDevice device) : mDevice(device) {
    vkGetPhysicalDeviceMemoryProperties(physicalDevice, &mMemoryProperties);
    VkPhysicalDeviceProperties props{};
    vkGetPhysicalDeviceProperties(physicalDevice, &props);
    mGranularity = std::max<VkDeviceSize>(1, props.limits.bufferImageGranularity);
    constexpr VkMemoryPropertyFlags kUnified =
        VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
    for (uint32_t i = 0; i < mMemoryProperties.memoryTypeCount; ++i) {
        if ((mMemoryProperties.memoryTypes[i].propertyFlags & kUnified) == kUnified) {
            mUnifiedMemory = true;
        }
    }
}

Allocator::~Allocator() {
    for (Block& b : mBlocks) {
        if (b.memory != VK_NULL_HANDLE) vkFreeMemory(mDevice, b.memory, nullptr);
    }
}

uint32_t Allocator::findMemoryType(uint32_t typeBits, MemoryUsage usage) const {
    // Ordered preference lists: the first (required, preferred) pair that some allowed type
    // satisfies wins.
    struct Want {
        VkMemoryPropertyFlags required, preferred;
    };
    std::vector<Want> wants;
    switch (usage) {
    case MemoryUsage::GpuOnly:
        wants = {{VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0}, {0, 0}};
        break;
    case MemoryUsage::Upload:
        wants = {{VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                  VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT},
                 {VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT, 0}};
        break;
    case MemoryUsage::Readback:
        wants = {{VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT, VK_MEMORY_PROPERTY_HOST_CACHED_BIT}};
        break;
    }
    for (const Want& w : wants) {
        uint32_t best = ~0u;
        for (uint32_t i = 0; i < mMemoryProperties.memoryTypeCount; ++i) {
            const VkMemoryPropertyFlags f = mMemoryProperties.memoryTypes[i].propertyFlags;
            if (!(typeBits & (1u << i)) || (f & w.required) != w.required) continue;
            if (best == ~0u || ((f & w.preferred) == w.preferred &&
                                (mMemoryProperties.memoryTypes[best].propertyFlags & w.preferred) !=
                                    w.preferred)) {
                best = i;
            }
        }
        if (best != ~0u) return best;
    }
    throw VulkanError(VK_ERROR_FEATURE_NOT_PRESENT, "no suitable memory type", __FILE__, __LINE__);
}

uint32_t Allocator::createBlock(uint32_t memoryType, VkDeviceSize size, bool dedicated) {
    VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    info.allocationSize = size;
    info.memoryTypeIndex = memoryType;
    Block block;
    GT_VK_CHECK(vkAllocateMemory(mDevice, &info, nullptr, &block.memory));
    block.size = size;
    block.memoryType = memoryType;
    block.dedicated = dedicated;
    const VkMemoryPropertyFlags flags = mMemoryProperties.memoryTypes[memoryType].propertyFlags;
    block.coherent = (flags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) != 0;
    if (flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) {
        void* ptr = nullptr;
        const VkResult r = vkMapMemory(mDevice, block.memory, 0, VK_WHOLE_SIZE, 0, &ptr);
        if (r != VK_SUCCESS) {
            vkFreeMemory(mDevice, block.memory, nullptr);
            throw VulkanError(r, "vkMapMemory", __FILE__, __LINE__);
        }
        block.mapped = static_cast<std::byte*>(ptr);
    }
    block.freeRanges.emplace(0, size);
    for (uint32_t i = 0; i < mBlocks.size(); ++i) {
        if (mBlocks[i].memory == VK_NULL_HANDLE) {
            mBlocks[i] = std::move(block);
            return i;
        }
    }
    mBlocks.push_back(std::move(block));
    return static_cast<uint32_t>(mBlocks.size() - 1);
}

bool Allocator::tryAllocateFrom(uint32_t blockIndex, const VkMemoryRequirements& req,
                                Allocation& out) {
    Block& b = mBlocks[blockIndex];
    const VkDeviceSize align = std::max(req.alignment, mGranularity);
    const VkDeviceSize size = alignUp(req.size, mGranularity);
    for (auto it = b.freeRanges.begin(); it != b.freeRanges.end(); ++it) {
        const VkDeviceSize start = alignUp(it->first, align);
        const VkDeviceSize end = it->first + it->second;
        if (start + size > end) continue;
        const VkDeviceSize rangeOffset = it->first;
        b.freeRanges.erase(it);
        if (start > rangeOffset) b.freeRanges.emplace(rangeOffset, start - rangeOffset);
        if (start + size < end) b.freeRanges.emplace(start + size, end - (start + size));
        out.memory = b.memory;
        out.offset = start;
        out.size = size;
        out.block = blockIndex;
        out.memoryType = b.memoryType;
        out.mapped = b.mapped ? b.mapped + start : nullptr;
        out.coherent = b.coherent;
        ++b.liveAllocations;
        return true;
    }
    return false;
}

Allocation Allocator::allocate(const VkMemoryRequirements& requirements, MemoryUsage usage) {
    const uint32_t type = findMemoryType(requirements.memoryTypeBits, usage);
    // More than the whole heap can never succeed; some drivers answer such a request only after
    // a long stall, or (overcommitting) not at all until the memory is touched.
    const VkMemoryHeap& heap =
        mMemoryProperties.memoryHeaps[mMemoryProperties.memoryTypes[type].heapIndex];
    if (requirements.size > heap.size) {
        throw VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY, "a request larger than its memory heap",
                          __FILE__, __LINE__);
    }
    Allocation out;
    if (requirements.size <= kBlockSize / 2) {
        for (uint32_t i = 0; i < mBlocks.size(); ++i) {
            if (mBlocks[i].memory != VK_NULL_HANDLE && mBlocks[i].memoryType == type &&
                !mBlocks[i].dedicated && tryAllocateFrom(i, requirements, out)) {
                return out;
            }
        }
        const uint32_t i = createBlock(type, kBlockSize, false);
        if (!tryAllocateFrom(i, requirements, out)) {
            throw VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY, "sub-allocation", __FILE__, __LINE__);
        }
        return out;
    }
    // Dedicated block, sized to the request.
    const uint32_t i = createBlock(type, alignUp(requirements.size, mGranularity), true);
    if (!tryAllocateFrom(i, requirements, out)) {
        throw VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY, "dedicated allocation", __FILE__,
                          __LINE__);
    }
    return out;
}

void Allocator::free(const Allocation& a) noexcept {
    if (!a.valid() || a.block >= mBlocks.size()) return;
    Block& b = mBlocks[a.block];
    auto [it, inserted] = b.freeRanges.emplace(a.offset, a.size);
    // Merge with the following and preceding free ranges.
    auto next = std::next(it);
    if (next != b.freeRanges.end() && it->first + it->second == next->first) {
        it->second += next->second;
        b.freeRanges.erase(next);
    }
    if (it != b.freeRanges.begin()) {
        auto prev = std::prev(it);
        if (prev->first + prev->second == it->first) {
            prev->second += it->second;
            b.freeRanges.erase(it);
        }
    }
    if (--b.liveAllocations == 0 && b.dedicated) {
        // Dedicated blocks go back to the driver at once; shared blocks are kept for reuse.
        vkFreeMemory(mDevice, b.memory, nullptr);
        b = Block{};
    }
}

AllocatorStats Allocator::stats() const noexcept {
    AllocatorStats s;
    for (const Block& b : mBlocks) {
        if (b.memory == VK_NULL_HANDLE) continue;
        ++s.blockCount;
        s.blockBytes += b.size;
        VkDeviceSize freeBytes = 0;
        for (const auto& [o, sz] : b.freeRanges)
            freeBytes += sz;
        s.usedBytes += b.size - freeBytes;
        s.allocationCount += b.liveAllocations;
    }
    return s;
}

} // namespace gt::vk
