#include "image_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include "filters.hpp"

namespace gt::quality {

namespace {
void checkSameSize(const RgbaImage& a, const RgbaImage& b) {
    if (a.width != b.width || a.height != b.height || a.pixels.size() != a.count() * 4 ||
        b.pixels.size() != b.count() * 4) {
        throw std::invalid_argument("image measures: the images differ in size");
    }
}

ScalarMap luma(const RgbaImage& img) {
    ScalarMap y(img.count());
    for (std::size_t p = 0; p < y.size(); ++p) {
        y[p] = 0.2126f * img.at(p, 0) + 0.7152f * img.at(p, 1) + 0.0722f * img.at(p, 2);
    }
    return y;
}
} // namespace

namespace {
// Per pixel, the mean over the colour channels of `f` applied to test - reference.
template <typename F>
ScalarMap channelMeanMap(const RgbaImage& reference, const RgbaImage& test, F f) {
    checkSameSize(reference, test);
    ScalarMap out(reference.count());
    for (std::size_t p = 0; p < out.size(); ++p) {
        float s = 0.0f;
        for (int c = 0; c < 3; ++c) {
            s += f(static_cast<float>(test.at(p, c)) - static_cast<float>(reference.at(p, c)));
        }
        out[p] = s / 3.0f;
    }
    return out;
}
} // namespace

ScalarMap squaredErrorMap(const RgbaImage& reference, const RgbaImage& test) {
    return channelMeanMap(reference, test, [](float d) { return d * d; });
}

ScalarMap absoluteErrorMap(const RgbaImage& reference, const RgbaImage& test) {
    return channelMeanMap(reference, test, [](float d) { return std::abs(d); });
}

double psnrDb(double mse) {
    return mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 99.0;
}

ScalarMap ssimMap(const RgbaImage& reference, const RgbaImage& test) {
    checkSameSize(reference, test);
    const uint32_t w = reference.width, h = reference.height;
    const ScalarMap x = luma(reference), y = luma(test);
    ScalarMap xx(x.size()), yy(x.size()), xy(x.size());
    for (std::size_t p = 0; p < x.size(); ++p) {
        xx[p] = x[p] * x[p];
        yy[p] = y[p] * y[p];
        xy[p] = x[p] * y[p];
    }
    const Kernel g = gaussianKernel(1.5, 5);
    const ScalarMap mx = convolveSeparable(x, w, h, g, g), my = convolveSeparable(y, w, h, g, g);
    const ScalarMap sxx = convolveSeparable(xx, w, h, g, g);
    const ScalarMap syy = convolveSeparable(yy, w, h, g, g);
    const ScalarMap sxy = convolveSeparable(xy, w, h, g, g);
    constexpr double c1 = (0.01 * 255.0) * (0.01 * 255.0), c2 = (0.03 * 255.0) * (0.03 * 255.0);
    ScalarMap out(x.size());
    for (std::size_t p = 0; p < out.size(); ++p) {
        const double ux = mx[p], uy = my[p];
        const double vx = std::max(0.0, sxx[p] - ux * ux), vy = std::max(0.0, syy[p] - uy * uy);
        const double cxy = sxy[p] - ux * uy;
        out[p] = static_cast<float>(((2.0 * ux * uy + c1) * (2.0 * cxy + c2)) /
                                    ((ux * ux + uy * uy + c1) * (vx + vy + c2)));
    }
    return out;
}

std::vector<uint8_t> darkNearBrightMask(const RgbaImage& ref, uint8_t darkBelow,
                                        uint8_t brightAbove, int radius) {
    const int w = static_cast<int>(ref.width), h = static_cast<int>(ref.height);
    auto maxChannel = [&](std::size_t p) {
        return std::max({ref.at(p, 0), ref.at(p, 1), ref.at(p, 2)});
    };
    // Per row, the horizontal distance to the nearest bright pixel in that row (two scans);
    // then a pixel is near a bright one when some row within `radius` has dx^2 + dy^2 <= r^2.
    constexpr int kFar = std::numeric_limits<int>::max() / 4;
    std::vector<int> dx(ref.count(), kFar);
    for (int y = 0; y < h; ++y) {
        int* row = dx.data() + static_cast<std::ptrdiff_t>(y) * w;
        int last = -kFar;
        for (int x = 0; x < w; ++x) {
            if (maxChannel(static_cast<std::size_t>(y) * w + x) > brightAbove) {
                last = x;
            }
            row[x] = x - last;
        }
        last = kFar;
        for (int x = w - 1; x >= 0; --x) {
            if (maxChannel(static_cast<std::size_t>(y) * w + x) > brightAbove) {
                last = x;
            }
            row[x] = std::min(row[x], last - x);
        }
    }
    std::vector<uint8_t> mask(ref.count(), 0);
    const int r2 = radius * radius;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t p = static_cast<std::size_t>(y) * w + x;
            if (maxChannel(p) >= darkBelow) {
                continue;
            }
            for (int dy = -radius; dy <= radius && !mask[p]; ++dy) {
                const int yy = y + dy;
                if (yy < 0 || yy >= h) {
                    continue;
                }
                const int d = dx[static_cast<std::size_t>(yy) * w + x];
                mask[p] = d <= radius && d * d + dy * dy <= r2 ? 1 : 0;
            }
        }
    }
    return mask;
}

} // namespace gt::quality
