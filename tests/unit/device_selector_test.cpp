#include <gtest/gtest.h>

#include "vk/device_selector.hpp"

namespace gt::vk {
namespace {

DeviceCandidate device(const char* name, VkPhysicalDeviceType type, bool ok = true) {
    return {name, type, VK_API_VERSION_1_3, true, ok, true};
}

TEST(DeviceSelector, PrefersDiscreteOverIntegratedOverCpu) {
    const std::vector<DeviceCandidate> c = {
        device("llvmpipe", VK_PHYSICAL_DEVICE_TYPE_CPU),
        device("Intel UHD", VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU),
        device("NVIDIA H100", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU)};
    EXPECT_EQ(chooseDevice(c, {}).index, 2u);
    EXPECT_EQ(chooseDevice({c[0], c[1]}, {}).index, 1u);
    EXPECT_EQ(chooseDevice({c[0]}, {}).index, 0u);
}

TEST(DeviceSelector, SkipsUnsuitableDevicesWithReasons) {
    const std::vector<DeviceCandidate> c = {
        device("old GPU", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, false),
        device("llvmpipe", VK_PHYSICAL_DEVICE_TYPE_CPU)};
    const DeviceChoice choice = chooseDevice(c, {});
    EXPECT_EQ(choice.index, 1u);
    ASSERT_EQ(choice.rejected.size(), 1u);
    EXPECT_NE(choice.rejected[0].find("old GPU"), std::string::npos);
}

TEST(DeviceSelector, OverrideByIndexOrNameSubstring) {
    const std::vector<DeviceCandidate> c = {
        device("NVIDIA H100", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU),
        device("llvmpipe (LLVM 15)", VK_PHYSICAL_DEVICE_TYPE_CPU)};
    EXPECT_EQ(chooseDevice(c, {.index = 1}).index, 1u);
    EXPECT_EQ(chooseDevice(c, {.nameContains = "LLVMPIPE"}).index, 1u);
    EXPECT_EQ(chooseDevice(c, {.nameContains = "h100"}).index, 0u);
    const DeviceChoice none = chooseDevice(c, {.nameContains = "radeon"});
    EXPECT_FALSE(none.index.has_value());
    EXPECT_NE(none.error.find("radeon"), std::string::npos);
    EXPECT_FALSE(chooseDevice(c, {.index = 7}).index.has_value());
}

TEST(DeviceSelector, NoDeviceAtAllIsAClearError) {
    const DeviceChoice choice = chooseDevice({}, {});
    EXPECT_FALSE(choice.index.has_value());
    EXPECT_NE(choice.error.find("no Vulkan device"), std::string::npos);
}

} // namespace
} // namespace gt::vk
