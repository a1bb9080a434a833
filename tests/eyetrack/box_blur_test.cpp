// The detector's 3x3 blur must give OpenCV's pixels exactly: the ray walk's crossings, and so
// every fit, depend on them.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "error.hpp"
#include "pupil/box_blur.hpp"

namespace gt::eyetrack {
namespace {

cv::Mat reference(const cv::Mat& src) {
    cv::Mat out;
    cv::blur(src, out, cv::Size(3, 3), cv::Point(-1, -1), cv::BORDER_REPLICATE);
    return out;
}

TEST(BoxBlur3x3, MatchesOpenCvOnEveryWindowSum) {
    cv::RNG rng(17);
    // Uniform noise reaches sums in the middle; narrow ranges at both ends reach the extremes,
    // so every sum 0..2295 (and its rounding) is met.
    for (const auto& [lo, hi] :
         {std::pair{0, 256}, std::pair{0, 12}, std::pair{244, 256}, std::pair{100, 160}}) {
        cv::Mat src(241, 321, CV_8UC1);
        rng.fill(src, cv::RNG::UNIFORM, lo, hi);
        cv::Mat out;
        boxBlur3x3(src, out);
        ASSERT_EQ(out.size(), src.size());
        EXPECT_EQ(cv::norm(out, reference(src), cv::NORM_INF), 0.0) << lo << ".." << hi;
    }
}

TEST(BoxBlur3x3, MatchesOpenCvAtTinySizesAndOnViews) {
    cv::RNG rng(5);
    for (const cv::Size size : {cv::Size(1, 1), cv::Size(2, 1), cv::Size(1, 3), cv::Size(2, 2),
                                cv::Size(3, 5), cv::Size(7, 2)}) {
        cv::Mat src(size, CV_8UC1);
        rng.fill(src, cv::RNG::UNIFORM, 0, 256);
        cv::Mat out;
        boxBlur3x3(src, out);
        EXPECT_EQ(cv::norm(out, reference(src), cv::NORM_INF), 0.0) << size;
    }
    // A region of a larger image: rows are strided and its edges replicate its own pixels.
    cv::Mat big(60, 80, CV_8UC1);
    rng.fill(big, cv::RNG::UNIFORM, 0, 256);
    const cv::Mat view = big(cv::Rect(13, 7, 31, 23));
    cv::Mat out;
    boxBlur3x3(view, out);
    cv::Mat copy = view.clone();
    EXPECT_EQ(cv::norm(out, reference(copy), cv::NORM_INF), 0.0);
}

TEST(BoxBlur3x3, RejectsOtherTypesAndInPlace) {
    cv::Mat colour(4, 4, CV_8UC3, cv::Scalar::all(9)), out;
    EXPECT_THROW(boxBlur3x3(colour, out), EyetrackError);
    cv::Mat grey(4, 4, CV_8UC1, cv::Scalar(9));
    EXPECT_THROW(boxBlur3x3(grey, grey), EyetrackError);
}

} // namespace
} // namespace gt::eyetrack
