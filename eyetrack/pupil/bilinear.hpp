#pragma once
// Bilinear grey levels of an 8-bit image, shared by the pupil detector's ray walk and the limbus
// search so that both read an edge at the same place.
#include <algorithm>
#include <cmath>
#include <cstddef>

#include <opencv2/core.hpp>

#include "error.hpp"

namespace gt::eyetrack {

// Which cell a bilinear sample at (x, y) reads: (x0, y0), the top left of the four pixels it
// blends (the last row and column fall in the cell before them); none outside the image. Shared
// by Bilinear and BilinearRange so that both put a sample in the same cell.
class BilinearCells {
public:
    BilinearCells() = default;
    explicit BilinearCells(const cv::Mat& img)
        : mMaxX(img.cols - 1.0), mMaxY(img.rows - 1.0), mLastX0(std::max(0, img.cols - 2)),
          mLastY0(std::max(0, img.rows - 2)) {}

    [[nodiscard]] bool cell(double x, double y, int& x0, int& y0) const {
        if (x < 0.0 || y < 0.0 || x > mMaxX || y > mMaxY) {
            return false;
        }
        x0 = std::min(static_cast<int>(x), mLastX0);
        y0 = std::min(static_cast<int>(y), mLastY0);
        return true;
    }
    [[nodiscard]] int lastY0() const { return mLastY0; }

private:
    double mMaxX = -1.0, mMaxY = -1.0;
    int mLastX0 = 0, mLastY0 = 0;
};

// Bilinear samples of an 8-bit image with pixel centres at integer coordinates; -1 outside the
// image. The image's bounds are read once: the ray walk samples tens of thousands of times a
// frame, a quarter of the detector's instructions, and reloading and converting them at each
// sample would add a third to that.
class Bilinear {
public:
    explicit Bilinear(const cv::Mat& img)
        : mCells(img), mData(img.data), mStep(img.step[0]), mNextX(img.cols > 1 ? 1 : 0),
          mNextY(img.rows > 1 ? img.step[0] : 0) {}

    [[nodiscard]] double operator()(double x, double y) const {
        int x0 = 0, y0 = 0;
        if (!mCells.cell(x, y, x0, y0)) {
            return -1.0;
        }
        const double fx = x - x0, fy = y - y0;
        const uchar* r0 = mData + static_cast<std::size_t>(y0) * mStep + x0;
        const uchar* r1 = r0 + mNextY;
        const double top = r0[0] + fx * (r0[mNextX] - r0[0]);
        const double bottom = r1[0] + fx * (r1[mNextX] - r1[0]);
        return top + fy * (bottom - top);
    }

private:
    BilinearCells mCells;
    const uchar* mData;
    std::size_t mStep;
    std::ptrdiff_t mNextX;
    std::size_t mNextY;
};

// The least and the greatest of the four pixels that Bilinear blends, per cell (the cell of a
// sample is its (x0, y0) there). A sample lies between them, in floating point too: each of
// Bilinear's two blends is a + f (b - a) with f in [0, 1] and ends a, b that are exact, and
// rounding is monotonic, so neither blend leaves [min(a, b), max(a, b)]. A threshold test on a
// sample whose cell lies wholly on one side of the threshold is therefore answered without the
// sample — what the ray walk asks at most of its steps (inside the pupil, and beyond its edge
// when looking for a glint's far side).
class BilinearRange {
public:
    enum class Side { Outside, Below, AtOrAbove, Straddles };

    BilinearRange() = default;
    explicit BilinearRange(const cv::Mat& img) { build(img); }

    // For an 8-bit single-channel image; the ranges are rebuilt in place (no allocation once
    // the size is known), with OpenCV's vectorised min and max: of each pixel and the one below,
    // then of each of those and the one to its right, over the rows laid end to end (a row's last
    // entry pairs with the next row's first: a cell Bilinear never uses, x0 <= cols - 2).
    void build(const cv::Mat& img) {
        if (img.empty() || img.type() != CV_8UC1) {
            throw EyetrackError("bilinear range: expected a non-empty 8-bit greyscale image");
        }
        mCells = BilinearCells(img);
        mCols = static_cast<std::size_t>(img.cols);
        const int cellRows = mCells.lastY0() + 1, nextY = img.rows > 1 ? 1 : 0;
        const int n = cellRows * img.cols;
        mColumnLo.create(1, n + 1, CV_8UC1);
        mColumnHi.create(1, n + 1, CV_8UC1);
        mLo.create(1, n, CV_8UC1);
        mHi.create(1, n, CV_8UC1);
        const cv::Mat flat = (img.isContinuous() ? img : img.clone()).reshape(1, 1);
        const cv::Mat top = flat.colRange(0, n),
                      bottom = flat.colRange(nextY * img.cols, n + nextY * img.cols);
        cv::Mat lo = mColumnLo.colRange(0, n), hi = mColumnHi.colRange(0, n);
        cv::min(top, bottom, lo);
        cv::max(top, bottom, hi);
        // The extra entry makes the last pair (x0 = cols - 1 of the last row, unused) defined;
        // a one-column image pairs each entry with itself.
        mColumnLo.at<uchar>(0, n) = mColumnLo.at<uchar>(0, n - 1);
        mColumnHi.at<uchar>(0, n) = mColumnHi.at<uchar>(0, n - 1);
        const int nextX = img.cols > 1 ? 1 : 0;
        cv::min(mColumnLo.colRange(0, n), mColumnLo.colRange(nextX, n + nextX), mLo);
        cv::max(mColumnHi.colRange(0, n), mColumnHi.colRange(nextX, n + nextX), mHi);
    }

    // A threshold as the least whole grey level at or above it: for a pixel value v,
    // v < level exactly when v < Level, and v >= level exactly when v >= Level.
    struct Level {
        int atOrAbove;
    };
    [[nodiscard]] static Level level(double threshold) {
        return {static_cast<int>(std::ceil(threshold))};
    }

    // Where Bilinear's sample at (x, y) lies against `level`, as far as its cell tells:
    // Outside where Bilinear returns -1, Straddles where only the sample can tell.
    [[nodiscard]] Side side(double x, double y, Level level) const {
        int x0 = 0, y0 = 0;
        if (!mCells.cell(x, y, x0, y0)) {
            return Side::Outside;
        }
        const std::size_t i = static_cast<std::size_t>(y0) * mCols + static_cast<std::size_t>(x0);
        if (mHi.data[i] < level.atOrAbove) {
            return Side::Below;
        }
        return mLo.data[i] >= level.atOrAbove ? Side::AtOrAbove : Side::Straddles;
    }

private:
    BilinearCells mCells;
    std::size_t mCols = 0;
    cv::Mat mLo, mHi, mColumnLo, mColumnHi;
};

} // namespace gt::eyetrack
