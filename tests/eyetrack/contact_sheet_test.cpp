// The contact sheet of a long clip shows the whole clip: its tiles spread evenly from the first
// frame to the last, not just its first 48 every-n-th frames (0..1175 of 3000 at every 25th).
#include <algorithm>
#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <unistd.h>

#include "formats/contact_sheet.hpp"

namespace gt::eyetrack {
namespace {

std::filesystem::path sheetPath(const std::string& name) {
    return std::filesystem::temp_directory_path() /
           ("gazetrace_sheet_" + name + "_" + std::to_string(::getpid()) + ".png");
}

// Largest and smallest step between successive frames.
std::pair<std::uint64_t, std::uint64_t> steps(const std::vector<std::uint64_t>& f) {
    std::uint64_t lo = UINT64_MAX, hi = 0;
    for (std::size_t i = 1; i < f.size(); ++i) {
        lo = std::min(lo, f[i] - f[i - 1]);
        hi = std::max(hi, f[i] - f[i - 1]);
    }
    return {lo, hi};
}

TEST(ContactSheet, SpreadFramesIncludesFirstAndLastEvenly) {
    const auto f = spreadFrames(3000, 48);
    ASSERT_EQ(f.size(), 48u);
    EXPECT_EQ(f.front(), 0u);
    EXPECT_EQ(f.back(), 2999u);
    const auto [lo, hi] = steps(f);
    EXPECT_GE(lo, 63u); // 2999 / 47 = 63.8
    EXPECT_LE(hi, 64u);
    EXPECT_EQ(spreadFrames(5, 48).size(), 5u);
    EXPECT_TRUE(spreadFrames(0, 48).empty());
}

TEST(ContactSheet, LongClipSpansTheWholeClip) {
    const auto png = sheetPath("long");
    ContactSheet sheet(png, 25);
    const cv::Mat grey(12, 16, CV_8UC1, cv::Scalar(90));
    for (std::uint64_t i = 0; i < 3000; ++i)
        sheet.add(grey, PupilResult{}, 1000 + i);
    const std::vector<std::uint64_t> shown = sheet.tileSequences();
    ASSERT_EQ(sheet.tiles(), ContactSheet::kMaxTiles);
    ASSERT_EQ(shown.size(), 48u);
    EXPECT_EQ(shown.front(), 1000u);
    EXPECT_EQ(shown.back(), 1000u + 2999u);
    const auto [lo, hi] = steps(shown);
    // Within a quarter of the even spacing (63.8 frames) of it.
    EXPECT_GE(lo, 48u);
    EXPECT_LE(hi, 80u);
    sheet.write();
    const cv::Mat img = cv::imread(png.string());
    EXPECT_EQ(img.cols, 6 * 16);
    EXPECT_EQ(img.rows, 8 * 12);
    std::filesystem::remove(png);
}

TEST(ContactSheet, ShortClipKeepsEveryNthFrame) {
    ContactSheet sheet(sheetPath("short"), 100);
    const cv::Mat grey(12, 16, CV_8UC1, cv::Scalar(90));
    for (std::uint64_t i = 0; i < 700; ++i)
        sheet.add(grey, PupilResult{}, i);
    EXPECT_EQ(sheet.tileSequences(), (std::vector<std::uint64_t>{0, 100, 200, 300, 400, 500, 600}));
}

} // namespace
} // namespace gt::eyetrack
