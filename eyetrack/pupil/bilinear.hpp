#pragma once
// Bilinear grey levels of an 8-bit image, shared by the pupil detector's ray walk and the limbus
// search so that both read an edge at the same place.
#include <algorithm>
#include <cstddef>

#include <opencv2/core.hpp>

namespace gt::eyetrack {

// Bilinear samples of an 8-bit image with pixel centres at integer coordinates; -1 outside the
// image. The image's bounds are read once: the ray walk samples tens of thousands of times a
// frame, a quarter of the detector's instructions, and reloading and converting them each time
// was a third of that.
class Bilinear {
public:
    explicit Bilinear(const cv::Mat& img)
        : mData(img.data), mStep(img.step[0]), mMaxX(img.cols - 1.0), mMaxY(img.rows - 1.0),
          mLastX0(std::max(0, img.cols - 2)), mLastY0(std::max(0, img.rows - 2)),
          mNextX(img.cols > 1 ? 1 : 0), mNextY(img.rows > 1 ? img.step[0] : 0) {}

    [[nodiscard]] double operator()(double x, double y) const {
        if (x < 0.0 || y < 0.0 || x > mMaxX || y > mMaxY) {
            return -1.0;
        }
        const int x0 = std::min(static_cast<int>(x), mLastX0);
        const int y0 = std::min(static_cast<int>(y), mLastY0);
        const double fx = x - x0, fy = y - y0;
        const uchar* r0 = mData + static_cast<std::size_t>(y0) * mStep + x0;
        const uchar* r1 = r0 + mNextY;
        const double top = r0[0] + fx * (r0[mNextX] - r0[0]);
        const double bottom = r1[0] + fx * (r1[mNextX] - r1[0]);
        return top + fy * (bottom - top);
    }

private:
    const uchar* mData;
    std::size_t mStep;
    double mMaxX, mMaxY;
    int mLastX0, mLastY0;
    std::ptrdiff_t mNextX;
    std::size_t mNextY;
};

} // namespace gt::eyetrack
