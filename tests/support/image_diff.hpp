#pragma once
// Comparing 8-bit images in tests.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

namespace gt::test {

// Mean absolute difference over every byte (RGBA8: 0-255 per channel, alpha included).
inline double meanAbsDiff(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
        d += std::abs(static_cast<int>(a[i]) - static_cast<int>(b[i]));
    }
    return a.empty() ? 0.0 : d / static_cast<double>(a.size());
}

// Root-mean-square difference over the colour channels of the pixels (x, y) of two RGBA8
// images `width` pixels wide for which keep(x, y) holds (alpha left out).
template <class Keep>
double rgbRmseWhere(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, uint32_t width,
                    Keep keep) {
    double se = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
        const std::size_t pixel = i / 4;
        if (i % 4 == 3 ||
            !keep(static_cast<uint32_t>(pixel % width), static_cast<uint32_t>(pixel / width))) {
            continue;
        }
        const double d = static_cast<double>(a[i]) - static_cast<double>(b[i]);
        se += d * d;
        ++n;
    }
    return n == 0 ? 0.0 : std::sqrt(se / static_cast<double>(n));
}

// The same over every pixel.
inline double rgbRmse(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    return rgbRmseWhere(a, b, 1, [](uint32_t, uint32_t) { return true; });
}

} // namespace gt::test
