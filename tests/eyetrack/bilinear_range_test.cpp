// The ray walk skips a sample wherever BilinearRange says which side of the threshold it lies
// on; the detector's answers stay the same only if that is never wrong.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>

#include "error.hpp"
#include "pupil/bilinear.hpp"

namespace gt::eyetrack {
namespace {

using Side = BilinearRange::Side;

// Checks every verdict against the sample itself at n points (integers, halves, the last row
// and column exactly, a little outside) and returns how many were decided without the sample.
int checkAgainstSamples(const cv::Mat& img, cv::RNG& rng, int n) {
    const Bilinear sample(img);
    const BilinearRange range(img);
    int decided = 0;
    for (int k = 0; k < n; ++k) {
        const auto coordinate = [&](int size) {
            switch (k % 4) {
            case 0:
                return rng.uniform(-1.0, size + 0.0);
            case 1:
                return std::round(rng.uniform(0.0, size - 1.0) * 2.0) / 2.0;
            case 2:
                return size - 1.0; // the last row or column exactly
            default:
                return rng.uniform(0.0, size - 1.0);
            }
        };
        const double x = coordinate(img.cols), y = coordinate(img.rows);
        // Whole levels (where < and >= meet a pixel value exactly) and fractional ones.
        const double level = k % 3 == 0 ? rng.uniform(0, 257) : rng.uniform(-0.5, 256.5);
        const double v = sample(x, y);
        const Side side = range.side(x, y, BilinearRange::level(level));
        if (v < 0.0) {
            EXPECT_EQ(side, Side::Outside) << x << "," << y;
            continue;
        }
        EXPECT_NE(side, Side::Outside) << x << "," << y;
        if (side == Side::Below) {
            EXPECT_LT(v, level) << x << "," << y;
            ++decided;
        } else if (side == Side::AtOrAbove) {
            EXPECT_GE(v, level) << x << "," << y;
            ++decided;
        }
    }
    return decided;
}

TEST(BilinearRange, NeverContradictsTheSample) {
    cv::RNG rng(23);
    // Smooth images (most cells decided) and noise (many straddle), at the detector's size.
    for (const bool smooth : {true, false}) {
        cv::Mat img(240, 320, CV_8UC1);
        rng.fill(img, cv::RNG::UNIFORM, 0, 256);
        if (smooth) {
            cv::GaussianBlur(img, img, cv::Size(0, 0), 6.0);
        }
        const int n = 200000;
        const int decided = checkAgainstSamples(img, rng, n);
        // The point of the range: on a smooth image most tests need no sample (on noise, with
        // levels anywhere in 0..256, a third or so are still decided).
        EXPECT_GT(decided, smooth ? n / 2 : n / 5) << (smooth ? "smooth" : "noise");
    }
}

TEST(BilinearRange, HoldsAtTinySizesAndOnViews) {
    cv::RNG rng(4);
    for (const cv::Size size : {cv::Size(1, 1), cv::Size(2, 1), cv::Size(1, 3), cv::Size(2, 2),
                                cv::Size(3, 5), cv::Size(7, 2)}) {
        cv::Mat img(size, CV_8UC1);
        rng.fill(img, cv::RNG::UNIFORM, 0, 256);
        checkAgainstSamples(img, rng, 4000);
    }
    // A region of a larger image: strided rows, read where they are.
    cv::Mat big(60, 80, CV_8UC1);
    rng.fill(big, cv::RNG::UNIFORM, 0, 256);
    checkAgainstSamples(big(cv::Rect(13, 7, 31, 23)), rng, 20000);
}

TEST(BilinearRange, WholeCellsOnOneSideAreDecided) {
    // A step image: cells wholly dark or wholly bright must be decided, the step's own cells
    // straddle.
    cv::Mat img(10, 10, CV_8UC1, cv::Scalar(20));
    img.colRange(5, 10).setTo(200);
    const BilinearRange range(img);
    const auto level = BilinearRange::level(100.0);
    EXPECT_EQ(range.side(1.5, 4.0, level), Side::Below);
    EXPECT_EQ(range.side(7.5, 4.0, level), Side::AtOrAbove);
    EXPECT_EQ(range.side(4.5, 4.0, level), Side::Straddles);
    EXPECT_EQ(range.side(9.0, 9.0, level), Side::AtOrAbove);
    EXPECT_EQ(range.side(9.01, 4.0, level), Side::Outside);
    EXPECT_EQ(range.side(-0.01, 4.0, level), Side::Outside);
    // A whole-number level: a pixel at it is at or above it.
    const cv::Mat flat(3, 3, CV_8UC1, cv::Scalar(100));
    EXPECT_EQ(BilinearRange(flat).side(1.0, 1.0, BilinearRange::level(100.0)), Side::AtOrAbove);
    EXPECT_EQ(BilinearRange(flat).side(1.0, 1.0, BilinearRange::level(100.5)), Side::Below);
}

TEST(BilinearRange, RejectsOtherImages) {
    BilinearRange range;
    EXPECT_THROW(range.build(cv::Mat()), EyetrackError);
    EXPECT_THROW(range.build(cv::Mat(4, 4, CV_8UC3, cv::Scalar::all(9))), EyetrackError);
}

} // namespace
} // namespace gt::eyetrack
