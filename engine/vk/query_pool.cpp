#include "vk/query_pool.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "vk/context.hpp"

namespace gt::vk {

TimestampPool::TimestampPool(Context& ctx, uint32_t count)
    : mDevice(ctx.device()), mCount(count), mPeriodNs(ctx.properties().limits.timestampPeriod),
      mSupported(ctx.properties().limits.timestampComputeAndGraphics == VK_TRUE) {
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = count;
    GT_VK_CHECK(vkCreateQueryPool(mDevice, &info, nullptr, &mPool));
    reset();
}

TimestampPool::~TimestampPool() {
    vkDestroyQueryPool(mDevice, mPool, nullptr);
}

void TimestampPool::reset() noexcept {
    vkResetQueryPool(mDevice, mPool, 0, mCount);
}

void TimestampPool::write(VkCommandBuffer cmd, uint32_t index, VkPipelineStageFlags2 stage) const {
    vkCmdWriteTimestamp2(cmd, stage, mPool, index);
}

std::vector<uint64_t> TimestampPool::read(uint32_t count) const {
    const uint32_t n = count == 0 ? mCount : std::min(count, mCount);
    std::vector<uint64_t> ticks(n, 0);
    if (n == 0) return ticks;
    const VkResult r = vkGetQueryPoolResults(mDevice, mPool, 0, n, ticks.size() * 8, ticks.data(),
                                             8, VK_QUERY_RESULT_64_BIT);
    if (r == VK_NOT_READY) return {};
    GT_VK_CHECK(r);
    return ticks;
}

} // namespace gt::vk
