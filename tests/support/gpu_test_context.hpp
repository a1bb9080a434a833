#pragma once
// Shared GPU test context (Falcor's GPU_TEST idea): one Vulkan context per test binary with the
// Khronos validation layer, synchronization validation and a real debug messenger. Every GPU
// test derives from GpuTest, whose TearDown fails the test on any new validation error.
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "vk/context.hpp"

namespace gt::test {

vk::Context& gpuContext();

class GpuTest : public ::testing::Test {
protected:
    void SetUp() override;
    void TearDown() override;
    vk::Context& ctx() { return gpuContext(); }

private:
    uint32_t mErrorsBefore = 0;
};

// ../shared/content, or empty when it is absent (tests then skip with a message).
std::filesystem::path sharedContent();

// A temporary folder unique to the running test, removed by the caller if wanted.
std::filesystem::path tempDir(const std::string& name);

} // namespace gt::test
