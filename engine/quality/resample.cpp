#include "resample.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace gt::quality {

namespace {
// The four source taps and weights of destination pixel `i` along one axis.
struct Taps {
    std::array<uint32_t, 4> at;
    std::array<float, 4> w;
};

Taps taps(uint32_t i, uint32_t src, uint32_t dst, Upscale filter) {
    const double f = (static_cast<double>(i) + 0.5) * src / dst - 0.5;
    const double base = std::floor(f);
    const auto t = static_cast<float>(f - base);
    Taps out{};
    for (int k = 0; k < 4; ++k) {
        const auto s = static_cast<long long>(base) + k - 1;
        out.at[static_cast<std::size_t>(k)] =
            static_cast<uint32_t>(std::clamp<long long>(s, 0, static_cast<long long>(src) - 1));
    }
    if (filter == Upscale::Bilinear) {
        out.w = {0.0f, 1.0f - t, t, 0.0f};
    } else {
        // Catmull-Rom (Keys' cubic with a = -0.5).
        const float t2 = t * t, t3 = t2 * t;
        out.w = {0.5f * (-t3 + 2.0f * t2 - t), 0.5f * (3.0f * t3 - 5.0f * t2 + 2.0f),
                 0.5f * (-3.0f * t3 + 4.0f * t2 + t), 0.5f * (t3 - t2)};
    }
    return out;
}
} // namespace

RgbaImage upscale(const RgbaImage& src, uint32_t width, uint32_t height, Upscale filter) {
    RgbaImage out{width, height,
                  std::vector<uint8_t>(static_cast<std::size_t>(width) * height * 4)};
    std::vector<Taps> tx(width);
    for (uint32_t x = 0; x < width; ++x) {
        tx[x] = taps(x, src.width, width, filter);
    }
    for (uint32_t y = 0; y < height; ++y) {
        const Taps ty = taps(y, src.height, height, filter);
        for (uint32_t x = 0; x < width; ++x) {
            for (int c = 0; c < 4; ++c) {
                float v = 0.0f;
                for (std::size_t j = 0; j < 4; ++j) {
                    if (ty.w[j] == 0.0f) {
                        continue;
                    }
                    float row = 0.0f;
                    for (std::size_t i = 0; i < 4; ++i) {
                        row +=
                            tx[x].w[i] *
                            static_cast<float>(src.at(
                                static_cast<std::size_t>(ty.at[j]) * src.width + tx[x].at[i], c));
                    }
                    v += ty.w[j] * row;
                }
                out.pixels[(static_cast<std::size_t>(y) * width + x) * 4 +
                           static_cast<std::size_t>(c)] =
                    static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
            }
        }
    }
    return out;
}

} // namespace gt::quality
