#pragma once
// A small device-memory sub-allocator in VMA's spirit (Debian packages no VMA): one list of
// 64 MiB blocks per memory type, first-fit sub-allocation with coalescing free ranges, and a
// dedicated block for anything larger. All-or-nothing: a failed allocate leaves no state behind.
#include <cstdint>
#include <map>
#include <vector>

#include <vulkan/vulkan.h>

namespace gt::vk {

enum class MemoryUsage {
    GpuOnly,  // device-local; uploads go through staging where it is not host-visible
    Upload,   // host-visible, written by the CPU every frame (uniforms, staging)
    Readback, // host-visible and preferably cached, read by the CPU
};

struct Allocation {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize offset = 0;
    VkDeviceSize size = 0;
    uint32_t block = ~0u;
    uint32_t memoryType = ~0u;
    std::byte* mapped = nullptr; // non-null when host-visible
    bool coherent = true;
    [[nodiscard]] bool valid() const noexcept { return memory != VK_NULL_HANDLE; }
};

struct AllocatorStats {
    std::size_t blockCount = 0;
    VkDeviceSize blockBytes = 0;
    VkDeviceSize usedBytes = 0;
    std::size_t allocationCount = 0;
};

class Allocator {
public:
    static constexpr VkDeviceSize kBlockSize = 64ull << 20;

    Allocator(VkPhysicalDevice physicalDevice, VkDevice device);
    ~Allocator();
    Allocator(const Allocator&) = delete;
    Allocator& operator=(const Allocator&) = delete;

    [[nodiscard]] Allocation allocate(const VkMemoryRequirements& requirements, MemoryUsage usage);
    void free(const Allocation& allocation) noexcept;
    [[nodiscard]] AllocatorStats stats() const noexcept;
    [[nodiscard]] bool isDeviceLocalHostVisible() const noexcept { return mUnifiedMemory; }

private:
    struct Block {
        VkDeviceMemory memory = VK_NULL_HANDLE;
        VkDeviceSize size = 0;
        uint32_t memoryType = 0;
        std::byte* mapped = nullptr;
        bool coherent = true;
        std::map<VkDeviceSize, VkDeviceSize> freeRanges; // offset -> size
        std::size_t liveAllocations = 0;
        bool dedicated = false;
    };
    [[nodiscard]] uint32_t findMemoryType(uint32_t typeBits, MemoryUsage usage) const;
    [[nodiscard]] bool tryAllocateFrom(uint32_t blockIndex, const VkMemoryRequirements& req,
                                       Allocation& out);
    uint32_t createBlock(uint32_t memoryType, VkDeviceSize size, bool dedicated);

    VkDevice mDevice;
    VkPhysicalDeviceMemoryProperties mMemoryProperties{};
    VkDeviceSize mGranularity = 1;
    bool mUnifiedMemory = false;
    std::vector<Block> mBlocks; // freed blocks keep their slot with memory == VK_NULL_HANDLE
};

} // namespace gt::vk
