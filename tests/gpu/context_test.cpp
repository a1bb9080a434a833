// The Vulkan context: a device is chosen, validation is live (a deliberate error is counted),
// and timestamps work.
#include "support/gpu_test_context.hpp"
#include "vk/query_pool.hpp"
#include "vk/resources.hpp"

namespace gt {
namespace {

class ContextTest : public test::GpuTest {};

TEST_F(ContextTest, HasDeviceAndValidation) {
    EXPECT_FALSE(ctx().deviceName().empty());
    EXPECT_GE(ctx().properties().apiVersion, VK_API_VERSION_1_3);
    // Validation must really report: every GPU test fails on a counted error, so a messenger
    // that counts nothing would pass them all. A context of its own makes a known mistake.
    vk::Context other({.validation = true, .announceDevice = false});
    ASSERT_TRUE(other.validationEnabled());
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = 0; // VUID-VkBufferCreateInfo-size-00912
    info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    VkBuffer b = VK_NULL_HANDLE;
    (void)vkCreateBuffer(other.device(), &info, nullptr, &b);
    if (b != VK_NULL_HANDLE) vkDestroyBuffer(other.device(), b, nullptr);
    EXPECT_GE(other.validationErrors(), 1u); // (the shared context's TearDown checks its own)
}

// The messenger must see errors raised after instance creation: make one
// on purpose on a separate context, and check it is counted.
TEST(ContextValidation, CountsDeliberateError) {
    vk::Context c({.validation = true, .synchronizationValidation = true, .announceDevice = false});
    const uint32_t before = c.validationErrors();
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = 0; // VUID-VkBufferCreateInfo-size-00912
    info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    VkBuffer buffer = VK_NULL_HANDLE;
    testing::internal::CaptureStderr();
    const VkResult r = vkCreateBuffer(c.device(), &info, nullptr, &buffer);
    (void)testing::internal::GetCapturedStderr();
    if (r == VK_SUCCESS && buffer != VK_NULL_HANDLE) vkDestroyBuffer(c.device(), buffer, nullptr);
    EXPECT_GT(c.validationErrors(), before);
}

TEST_F(ContextTest, TimestampsMeasureWork) {
    // A 64 MiB fill against a 4 KiB one: 16,000 times the work must take measurably longer
    // (equal or zero ticks, which the old `>=` check accepted, fail here).
    vk::Buffer buf(ctx(), {64u << 20,
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                           vk::MemoryUsage::GpuOnly, "t"});
    auto measure = [&](VkDeviceSize bytes) {
        vk::TimestampPool pool(ctx(), 2);
        ctx().submitAndWait([&](VkCommandBuffer cmd) {
            pool.write(cmd, 0, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT);
            vkCmdFillBuffer(cmd, buf.handle(), 0, bytes, 7);
            pool.write(cmd, 1, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT);
        });
        const auto ticks = pool.read();
        EXPECT_EQ(ticks.size(), 2u);
        EXPECT_GT(ticks[0], 0u);
        return ticks.size() == 2 ? static_cast<double>(ticks[1] - ticks[0]) * pool.tickToMs() : 0.0;
    };
    const double small = measure(4096);
    const double big = measure(64u << 20);
    EXPECT_GT(big, 0.0);
    EXPECT_GT(big, small);
}

TEST_F(ContextTest, UploadAndDownloadRoundTrip) {
    std::vector<uint32_t> data(4096);
    for (uint32_t i = 0; i < data.size(); ++i)
        data[i] = i * 2654435761u;
    vk::Buffer gpu(ctx(), {data.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                           vk::MemoryUsage::GpuOnly, "gpu"});
    gpu.upload(std::as_bytes(std::span(data)));
    vk::Buffer host(ctx(), {data.size() * 4, 0, vk::MemoryUsage::Readback, "host"});
    ctx().submitAndWait([&](VkCommandBuffer cmd) {
        VkBufferCopy region{0, 0, data.size() * 4};
        vkCmdCopyBuffer(cmd, gpu.handle(), host.handle(), 1, &region);
    });
    std::vector<uint32_t> back(data.size());
    host.download(std::as_writable_bytes(std::span(back)));
    EXPECT_EQ(back, data);
}

} // namespace
} // namespace gt
