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
            for (int k = -rx; k <= rx; ++k) {
                sum += kx[static_cast<std::size_t>(k + rx)] * in[std::clamp(x + k, 0, w - 1)];
            }
            out[x] = sum;
        }
    }
    ScalarMap out(src.size());
    for (int y = 0; y < h; ++y) {
        float* o = out.data() + static_cast<std::ptrdiff_t>(y) * w;
        for (int k = -ry; k <= ry; ++k) {
            const float c = ky[static_cast<std::size_t>(k + ry)];
            const float* in =
                rows.data() + static_cast<std::ptrdiff_t>(std::clamp(y + k, 0, h - 1)) * w;
            for (int x = 0; x < w; ++x) {
                o[x] += c * in[x];
            }
        }
    }
    return out;
}

Kernel gaussianKernel(double sigma, int radius) {
    Kernel k(static_cast<std::size_t>(2 * radius + 1));
    double sum = 0.0;
    for (int i = -radius; i <= radius; ++i) {
        const double v = std::exp(-static_cast<double>(i * i) / (2.0 * sigma * sigma));
        k[static_cast<std::size_t>(i + radius)] = static_cast<float>(v);
        sum += v;
    }
    for (float& v : k) {
        v = static_cast<float>(v / sum);
    }
    return k;
}

} // namespace gt::quality
