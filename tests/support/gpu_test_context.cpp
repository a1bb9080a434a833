#include "support/gpu_test_context.hpp"

#include <memory>

#include "option_parsing.hpp"

namespace gt::test {

vk::Context& gpuContext() {
    static std::unique_ptr<vk::Context> ctx = [] {
        return std::make_unique<vk::Context>(
            vk::ContextOptions{.validation = true,
                               .synchronizationValidation = true,
                               .deviceOverride = app::deviceRequest(),
                               .announceDevice = false});
    }();
    return *ctx;
}

void GpuTest::SetUp() {
    mErrorsBefore = gpuContext().validationErrors();
}

void GpuTest::TearDown() {
    const uint32_t now = gpuContext().validationErrors();
    EXPECT_EQ(now, mErrorsBefore) << "Vulkan validation errors during this test";
    if (now != mErrorsBefore) {
        const auto messages = gpuContext().validationMessages();
        for (std::size_t i = mErrorsBefore; i < messages.size(); ++i) {
            ADD_FAILURE() << messages[i];
        }
    }
}

std::filesystem::path sharedContent() {
    const std::filesystem::path p = GT_SHARED_CONTENT_DIR;
    std::error_code ec;
    return std::filesystem::is_directory(p, ec) ? p : std::filesystem::path{};
}

std::filesystem::path tempDir(const std::string& name) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::filesystem::path p =
        std::filesystem::temp_directory_path() /
        ("gazetrace_test_" + name + "_" + (info ? std::string(info->name()) : std::string("x")));
    std::filesystem::remove_all(p);
    std::filesystem::create_directories(p);
    return p;
}

} // namespace gt::test
