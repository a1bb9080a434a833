#pragma once
// Small image measurements the starburst pupil detector's stages share: bilinear samples, box sums
// on an integral image, grey-level percentiles of a box and points along an ellipse's outline.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <opencv2/core.hpp>

#include "pupil/bilinear.hpp"

namespace gt::eyetrack::starburst {

// Bilinear grey level at (x, y); -1 off the image.
inline double sample(const cv::Mat& img, double x, double y) {
    return Bilinear(img)(x, y);
}

// Sum over [x0, x1) x [y0, y1) from a CV_32S integral image.
inline long long boxSum(const cv::Mat& ii, int x0, int y0, int x1, int y1) {
    const int* a = ii.ptr<int>(y0);
    const int* b = ii.ptr<int>(y1);
    return static_cast<long long>(b[x1]) - b[x0] - a[x1] + a[x0];
}

// The square of half-side `half` (at least 1) around c, on whole pixels.
inline cv::Rect boxAround(cv::Point2d c, double half) {
    const int h = std::max(1, static_cast<int>(std::lround(half)));
    return {static_cast<int>(std::lround(c.x)) - h, static_cast<int>(std::lround(c.y)) - h,
            2 * h + 1, 2 * h + 1};
}

// Percentile q of the grey levels in a rectangle (sparse sampling for large ones), optionally
// excluding an inner rectangle; -1 when nothing of it is on the image.
[[nodiscard]] double percentile(const cv::Mat& img, cv::Rect outer, cv::Rect hole, double q);

// 0 below lo, 1 above hi, a smooth cubic ramp between.
inline double smoothstep(double lo, double hi, double x) {
    const double t = std::clamp((x - lo) / (hi - lo), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// Calls fn(point, unit outward normal) at `count` evenly spaced parameter angles on an ellipse.
template <typename Fn> void forEachOutlinePoint(const cv::RotatedRect& e, int count, Fn&& fn) {
    const double th = e.angle * std::numbers::pi / 180.0;
    const cv::Point2d u(std::cos(th), std::sin(th)), v(-std::sin(th), std::cos(th));
    const double a = 0.5 * e.size.width, b = 0.5 * e.size.height;
    const cv::Point2d c(e.center.x, e.center.y);
    for (int k = 0; k < count; ++k) {
        const double phi = (k + 0.5) * 2.0 * std::numbers::pi / count;
        const cv::Point2d n = u * (std::cos(phi) / a) + v * (std::sin(phi) / b);
        fn(c + u * (a * std::cos(phi)) + v * (b * std::sin(phi)), n * (1.0 / cv::norm(n)));
    }
}

} // namespace gt::eyetrack::starburst
