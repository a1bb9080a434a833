#include "filters.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace gt::quality {

ScalarMap convolveSeparable(const ScalarMap& src, uint32_t width, uint32_t height, const Kernel& kx,
                            const Kernel& ky) {
    const int w = static_cast<int>(width), h = static_cast<int>(height);
    const int rx = static_cast<int>(kx.size() / 2), ry = static_cast<int>(ky.size() / 2);
    ScalarMap rows(src.size());
    for (int y = 0; y < h; ++y) {
        const float* in = src.data() + static_cast<std::ptrdiff_t>(y) * w;
        float* out = rows.data() + static_cast<std::ptrdiff_t>(y) * w;
        for (int x = 0; x < w; ++x) {
            float sum = 0.0f;
            for (std::size_t j = 0; j < kx.size(); ++j) {
                sum += kx[j] * in[std::clamp(x + static_cast<int>(j) - rx, 0, w - 1)];
            }
            out[x] = sum;
        }
    }
    ScalarMap out(src.size());
    for (int y = 0; y < h; ++y) {
        float* o = out.data() + static_cast<std::ptrdiff_t>(y) * w;
        for (std::size_t j = 0; j < ky.size(); ++j) {
            const float c = ky[j];
            const int from = std::clamp(y + static_cast<int>(j) - ry, 0, h - 1);
            const float* in = rows.data() + static_cast<std::ptrdiff_t>(from) * w;
            for (int x = 0; x < w; ++x) {
                o[x] += c * in[x];
            }
        }
    }
    return out;
}

Kernel gaussianKernel(double sigma, int radius) {
    Kernel k(2 * static_cast<std::size_t>(radius) + 1);
    double sum = 0.0;
    for (std::size_t j = 0; j < k.size(); ++j) {
        const double i = static_cast<double>(j) - radius;
        const double v = std::exp(-i * i / (2.0 * sigma * sigma));
        k[j] = static_cast<float>(v);
        sum += v;
    }
    for (float& v : k) {
        v = static_cast<float>(v / sum);
    }
    return k;
}

} // namespace gt::quality
