#include "trace/texture_mips.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace gt::trace {
namespace {

// sRGB transfer (IEC 61966-2-1), as the shaders decode texels.
float srgbToLinear(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linearToSrgb(float c) {
    return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

using Texel = std::array<float, 4>;

// The texels of a side of n that texel i of the halved side covers: 2i and 2i + 1, the last
// also 2i + 2 when n is odd (so no texel is left out), or just 0 when n is 1.
std::pair<uint32_t, uint32_t> cover(uint32_t i, uint32_t n) {
    if (n == 1) {
        return {0, 1};
    }
    const uint32_t last = n / 2 - 1;
    return {2 * i, i == last && n % 2 == 1 ? 2 * i + 3 : 2 * i + 2};
}

// Level `from` (w x h, decoded) halved.
std::vector<Texel> halve(const std::vector<Texel>& from, uint32_t w, uint32_t h) {
    const uint32_t nw = std::max(1u, w / 2), nh = std::max(1u, h / 2);
    std::vector<Texel> out(static_cast<std::size_t>(nw) * nh);
    for (uint32_t y = 0; y < nh; ++y) {
        const auto [y0, y1] = cover(y, h);
        for (uint32_t x = 0; x < nw; ++x) {
            const auto [x0, x1] = cover(x, w);
            Texel sum{};
            for (uint32_t sy = y0; sy < y1; ++sy) {
                for (uint32_t sx = x0; sx < x1; ++sx) {
                    const Texel& t = from[static_cast<std::size_t>(sy) * w + sx];
                    for (std::size_t c = 0; c < 4; ++c) {
                        sum[c] += t[c];
                    }
                }
            }
            const auto n = static_cast<float>((x1 - x0) * (y1 - y0));
            for (float& c : sum) {
                c /= n;
            }
            out[static_cast<std::size_t>(y) * nw + x] = sum;
        }
    }
    return out;
}

uint32_t encode(const Texel& t, bool srgb) {
    uint32_t packed = 0;
    for (std::size_t c = 0; c < 4; ++c) {
        const float v = srgb && c < 3 ? linearToSrgb(t[c]) : t[c];
        const auto byte = static_cast<uint32_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
        packed |= byte << (8 * c);
    }
    return packed;
}

} // namespace

uint32_t mipLevelCount(uint32_t width, uint32_t height) noexcept {
    uint32_t levels = 1;
    for (uint32_t s = std::max(width, height); s > 1; s /= 2) {
        ++levels;
    }
    return levels;
}

std::vector<uint32_t> mipChain(const scene::Texture& texture, bool srgb) {
    std::array<float, 256> decode{};
    for (std::size_t i = 0; i < decode.size(); ++i) {
        const float v = static_cast<float>(i) / 255.0f;
        decode[i] = srgb ? srgbToLinear(v) : v;
    }
    std::vector<Texel> level(texture.rgba.size());
    for (std::size_t i = 0; i < level.size(); ++i) {
        const uint32_t p = texture.rgba[i];
        level[i] = {decode[p & 0xffu], decode[(p >> 8) & 0xffu], decode[(p >> 16) & 0xffu],
                    static_cast<float>(p >> 24) / 255.0f};
    }
    std::vector<uint32_t> out;
    uint32_t w = texture.width, h = texture.height;
    for (uint32_t l = 1; l < mipLevelCount(texture.width, texture.height); ++l) {
        level = halve(level, w, h);
        w = std::max(1u, w / 2);
        h = std::max(1u, h / 2);
        for (const Texel& t : level) {
            out.push_back(encode(t, srgb));
        }
    }
    return out;
}

} // namespace gt::trace
