// The one file reader (io/input_file.hpp) and the checked size arithmetic (io/checked_size.hpp):
// FIFOs, devices, folders, huge and sparse files are refused with a line naming the file, and
// sums and products that wrap around are reported, not truncated.
#include <cstdint>
#include <fstream>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include "checked_size.hpp"
#include "input_file.hpp"
#include "limits.hpp"
#include "support/gpu_test_context.hpp"

namespace gt {
namespace {

constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();

std::string errorOf(const std::filesystem::path& p, std::uint64_t limit) {
    try {
        (void)io::readInputFile(p, limit);
    } catch (const io::InputError& e) {
        return e.what();
    }
    return {};
}

TEST(CheckedSize, SumsAndProductsThatWrapAreReported) {
    EXPECT_EQ(io::checkedAdd(1, 2), 3U);
    EXPECT_FALSE(io::checkedAdd(kMax, 1));
    EXPECT_FALSE(io::checkedAdd(0xFFFFFFFFFFFFFFFCULL, 8));
    EXPECT_EQ(io::checkedMul(1U << 20, 1U << 20), 1ULL << 40);
    EXPECT_FALSE(io::checkedMul(0x4000000000000001ULL, 4));
}

TEST(CheckedSize, RangesThatWrapDoNotFit) {
    EXPECT_TRUE(io::rangeFits(0, 16, 16));
    EXPECT_TRUE(io::rangeFits(16, 0, 16));
    EXPECT_FALSE(io::rangeFits(8, 9, 16));
    EXPECT_FALSE(io::rangeFits(17, 0, 16));
    // offset + length wraps to 4: the naive `offset + length <= size` check passes.
    EXPECT_FALSE(io::rangeFits(0xFFFFFFFFFFFFFFFCULL, 8, 16));
    EXPECT_FALSE(io::rangeFits(8, kMax, 16));
}

TEST(CheckedSize, StridedSpansThatWrapAreReported) {
    EXPECT_EQ(io::stridedSpan(0, 12, 12), 0U);
    EXPECT_EQ(io::stridedSpan(3, 16, 12), 44U);
    // count * stride wraps to a small number.
    EXPECT_FALSE(io::stridedSpan(0x4000000000000001ULL, 4, 4));
    EXPECT_FALSE(io::stridedSpan(2, kMax, 4));
    EXPECT_FALSE(io::nonNegative(-4));
    EXPECT_EQ(io::nonNegative(4), 4U);
}

TEST(InputFile, ReadsARegularFileWhole) {
    const auto p = test::tempDir("input_file") / "a.txt";
    std::ofstream(p) << "hello";
    EXPECT_EQ(io::readInputFile(p, 5), "hello");
    EXPECT_EQ(io::checkInputFile(p, 5), 5U);
}

TEST(InputFile, FilesOverTheLimitAreRefusedBeforeReading) {
    const auto p = test::tempDir("input_file") / "a.txt";
    std::ofstream(p) << "hello!";
    const std::string e = errorOf(p, 5);
    EXPECT_NE(e.find(p.string()), std::string::npos) << e;
    EXPECT_NE(e.find("limit"), std::string::npos) << e;
}

TEST(InputFile, AFifoIsRefusedWithoutBlocking) {
    const auto p = test::tempDir("input_fifo") / "pipe";
    ASSERT_EQ(::mkfifo(p.c_str(), 0600), 0);
    const std::string e = errorOf(p, 1024);
    EXPECT_NE(e.find("FIFO"), std::string::npos) << e;
}

TEST(InputFile, DevicesFoldersAndSymlinksToDevicesAreRefused) {
    EXPECT_NE(errorOf("/dev/zero", kMax).find("character device"), std::string::npos);
    const auto dir = test::tempDir("input_links");
    const auto link = dir / "trace.csv";
    std::filesystem::create_symlink("/dev/zero", link);
    const std::string e = errorOf(link, kMax);
    EXPECT_NE(e.find(link.string()), std::string::npos) << e;
    EXPECT_NE(e.find("character device"), std::string::npos) << e;
    EXPECT_NE(errorOf(dir, kMax).find("a folder"), std::string::npos);
    EXPECT_NE(errorOf(dir / "missing", kMax).find("no such file"), std::string::npos);
}

TEST(InputFile, ASparseFileIsRefused) {
    const auto p = test::tempDir("input_sparse") / "scene.gltf";
    std::ofstream(p).put('x');
    std::filesystem::resize_file(p, 1ULL << 30);
    const std::string e = errorOf(p, kMax);
    EXPECT_NE(e.find("sparse"), std::string::npos) << e;
}

TEST(InputFile, SameFileSeesThroughLinksAndSpellings) {
    const auto dir = test::tempDir("input_same");
    std::ofstream(dir / "a") << "x";
    std::filesystem::create_symlink(dir / "a", dir / "b");
    EXPECT_TRUE(io::sameFile(dir / "a", dir / "b"));
    EXPECT_TRUE(io::sameFile(dir / "a", dir / "." / "a"));
    std::ofstream(dir / "c") << "x";
    EXPECT_FALSE(io::sameFile(dir / "a", dir / "c"));
    EXPECT_FALSE(io::sameFile(dir / "a", dir / "missing"));
}

TEST(InputFile, SizesInMessagesReadAsUnits) {
    EXPECT_EQ(io::describeBytes(17), "17 bytes");
    EXPECT_EQ(io::describeBytes(2 * io::limits::kGiB), "2.0 GiB");
    EXPECT_EQ(io::describeBytes(512 * io::limits::kKiB), "512 KiB");
}

} // namespace
} // namespace gt
