#include "pupil/box_blur.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

#include "error.hpp"

namespace gt::eyetrack {

void boxBlur3x3(const cv::Mat& src, cv::Mat& dst) {
    if (src.type() != CV_8UC1) {
        throw EyetrackError("3x3 blur: expected an 8-bit greyscale image");
    }
    if (src.data == dst.data && !src.empty()) {
        throw EyetrackError("3x3 blur: the output must not be the input");
    }
    dst.create(src.size(), CV_8UC1);
    const int w = src.cols, h = src.rows;
    if (w == 0 || h == 0) {
        return;
    }
    // Column sums of three rows, with one replicated column at each end so the horizontal pass
    // needs no edge cases.
    thread_local std::vector<std::uint16_t> column;
    column.resize(static_cast<std::size_t>(w) + 2);
    for (int y = 0; y < h; ++y) {
        {
            const uchar* __restrict above = src.ptr<uchar>(std::max(0, y - 1));
            const uchar* __restrict here = src.ptr<uchar>(y);
            const uchar* __restrict below = src.ptr<uchar>(std::min(h - 1, y + 1));
            std::uint16_t* __restrict c = column.data() + 1;
            for (int x = 0; x < w; ++x) {
                c[x] = static_cast<std::uint16_t>(above[x] + here[x] + below[x]);
            }
            c[-1] = c[0];
            c[w] = c[w - 1];
        }
        uchar* __restrict out = dst.ptr<uchar>(y);
        const std::uint16_t* __restrict cs = column.data() + 1;
        for (int x = 0; x < w; ++x) {
            // (sum + 4) / 9 for sums up to 2299, as a 16-bit multiply-high: exact there, and
            // eight or sixteen pixels to an instruction.
            const auto sum = static_cast<std::uint16_t>(cs[x - 1] + cs[x] + cs[x + 1] + 4u);
            out[x] = static_cast<uchar>((static_cast<std::uint32_t>(sum) * 7282u) >> 16);
        }
    }
}

} // namespace gt::eyetrack
