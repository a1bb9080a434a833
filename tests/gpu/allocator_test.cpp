// The sub-allocator: allocations do not overlap, frees coalesce, big requests get their own
// block, and everything returns to zero.
#include <algorithm>

#include "support/gpu_test_context.hpp"
#include "vk/resources.hpp"

namespace gt {
namespace {

class AllocatorTest : public test::GpuTest {};

// No two live buffers share a byte of the same memory block (an allocator handing out offset 0
// every time passed the counts this test checked before).
void expectDisjoint(const std::vector<vk::Buffer>& buffers) {
    std::vector<const vk::Allocation*> live;
    for (const vk::Buffer& b : buffers) {
        if (b.valid()) live.push_back(&b.allocation());
    }
    for (std::size_t i = 0; i < live.size(); ++i) {
        for (std::size_t j = i + 1; j < live.size(); ++j) {
            const vk::Allocation& a = *live[i];
            const vk::Allocation& c = *live[j];
            if (a.memory != c.memory) continue;
            const bool apart = a.offset + a.size <= c.offset || c.offset + c.size <= a.offset;
            EXPECT_TRUE(apart) << "[" << a.offset << ", +" << a.size << ") overlaps [" << c.offset
                               << ", +" << c.size << ")";
        }
    }
}

TEST_F(AllocatorTest, SubAllocatesWithoutOverlapAndFreesEverything) {
    const auto before = ctx().allocator().stats();
    {
        std::vector<vk::Buffer> buffers;
        for (int i = 0; i < 64; ++i) {
            buffers.emplace_back(ctx(), vk::BufferDesc{static_cast<VkDeviceSize>(1000 + 4096 * i),
                                                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                                       vk::MemoryUsage::GpuOnly, "a"});
        }
        const auto mid = ctx().allocator().stats();
        EXPECT_EQ(mid.allocationCount, before.allocationCount + 64);
        expectDisjoint(buffers);
        EXPECT_LE(mid.blockCount, before.blockCount + 2); // shared 64 MiB blocks, not 64
        // Free every other one, then allocate again into the holes.
        for (std::size_t i = 0; i < buffers.size(); i += 2)
            buffers[i] = vk::Buffer();
        for (int i = 0; i < 32; ++i) {
            buffers.emplace_back(ctx(), vk::BufferDesc{2048, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                                       vk::MemoryUsage::GpuOnly, "b"});
        }
        EXPECT_EQ(ctx().allocator().stats().allocationCount, before.allocationCount + 64);
        expectDisjoint(buffers); // the new ones went into the holes, not over the survivors
    }
    const auto after = ctx().allocator().stats();
    EXPECT_EQ(after.allocationCount, before.allocationCount);
    EXPECT_EQ(after.usedBytes, before.usedBytes);
}

TEST_F(AllocatorTest, LargeRequestGetsDedicatedBlockReleasedOnFree) {
    const auto before = ctx().allocator().stats();
    {
        vk::Buffer big(ctx(), {vk::Allocator::kBlockSize, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                               vk::MemoryUsage::GpuOnly, "big"});
        EXPECT_EQ(ctx().allocator().stats().blockCount, before.blockCount + 1);
    }
    EXPECT_EQ(ctx().allocator().stats().blockCount, before.blockCount);
}

} // namespace
} // namespace gt
