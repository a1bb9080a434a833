#pragma once
// GPU timestamp queries: one pair per render-graph pass, read back after the frame.
#include <cstdint>
#include <optional>
#include <vector>

#include <vulkan/vulkan.h>

namespace gt::vk {

class Context;

class TimestampPool {
public:
    TimestampPool(Context& ctx, uint32_t count);
    ~TimestampPool();
    TimestampPool(const TimestampPool&) = delete;
    TimestampPool& operator=(const TimestampPool&) = delete;

    [[nodiscard]] uint32_t capacity() const noexcept { return mCount; }
    void reset() noexcept; // host reset (Vulkan 1.2 hostQueryReset)
    void write(VkCommandBuffer cmd, uint32_t index, VkPipelineStageFlags2 stage) const;
    // Milliseconds between query `begin` and `end`; empty when not available or invalid.
    // The first `count` queries (all when 0); a query never written reads as not ready.
    [[nodiscard]] std::vector<uint64_t> read(uint32_t count = 0) const;
    [[nodiscard]] double tickToMs() const noexcept { return mPeriodNs * 1e-6; }
    [[nodiscard]] bool supported() const noexcept { return mSupported; }

private:
    VkDevice mDevice;
    VkQueryPool mPool = VK_NULL_HANDLE;
    uint32_t mCount;
    double mPeriodNs;
    bool mSupported;
};

} // namespace gt::vk
