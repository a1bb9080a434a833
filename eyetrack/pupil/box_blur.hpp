#pragma once

#include <opencv2/core.hpp>

namespace gt::eyetrack {

// The 3x3 mean of an 8-bit greyscale image, edges replicated, rounded to the nearest grey level:
// the same pixels as cv::blur(src, dst, {3, 3}, {-1, -1}, cv::BORDER_REPLICATE) (a sum of nine
// pixels over 9 never ends in exactly one half, so every correct rounding agrees). OpenCV's
// general box filter takes about four times the instructions of these two vectorised passes,
// which matters as the blur runs on every frame. `dst` must not share memory with `src`.
void boxBlur3x3(const cv::Mat& src, cv::Mat& dst);

} // namespace gt::eyetrack
