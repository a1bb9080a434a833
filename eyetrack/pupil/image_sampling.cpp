#include "pupil/image_sampling.hpp"

#include <array>

namespace gt::eyetrack::starburst {

double percentile(const cv::Mat& img, cv::Rect outer, cv::Rect hole, double q) {
    outer &= cv::Rect(0, 0, img.cols, img.rows);
    std::array<int, 256> hist{};
    int count = 0;
    const int step = std::max(1, static_cast<int>(std::sqrt(outer.area() / 1500.0)));
    for (int y = outer.y; y < outer.y + outer.height; y += step) {
        const uchar* row = img.ptr<uchar>(y);
        for (int x = outer.x; x < outer.x + outer.width; x += step) {
            if (hole.contains({x, y})) continue;
            ++hist[row[x]];
            ++count;
        }
    }
    if (count == 0) return -1.0;
    const int target = static_cast<int>(q * (count - 1));
    int acc = 0;
    for (int v = 0; v < 256; ++v) {
        acc += hist[static_cast<std::size_t>(v)];
        if (acc > target) return v;
    }
    return 255.0;
}

} // namespace gt::eyetrack::starburst
