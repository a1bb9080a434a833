#include "eval_plots.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace gt::app {

namespace {
constexpr std::array<std::array<uint8_t, 3>, 8> kPalette{{{31, 119, 180},
                                                          {255, 127, 14},
                                                          {44, 160, 44},
                                                          {214, 39, 40},
                                                          {148, 103, 189},
                                                          {140, 86, 75},
                                                          {227, 119, 194},
                                                          {127, 127, 127}}};

quality::RgbaImage canvas(uint32_t w, uint32_t h) {
    return {w, h, std::vector<uint8_t>(static_cast<std::size_t>(w) * h * 4, 255)};
}

void put(quality::RgbaImage& img, int x, int y, std::array<uint8_t, 3> c) {
    if (x < 0 || y < 0 || x >= static_cast<int>(img.width) || y >= static_cast<int>(img.height)) {
        return;
    }
    const std::size_t p =
        (static_cast<std::size_t>(y) * img.width + static_cast<std::size_t>(x)) * 4;
    img.pixels[p] = c[0];
    img.pixels[p + 1] = c[1];
    img.pixels[p + 2] = c[2];
}

void fill(quality::RgbaImage& img, int x0, int y0, int x1, int y1, std::array<uint8_t, 3> c) {
    for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
            put(img, x, y, c);
        }
    }
}

void line(quality::RgbaImage& img, double x0, double y0, double x1, double y1,
          std::array<uint8_t, 3> c) {
    const int steps = static_cast<int>(std::max(std::abs(x1 - x0), std::abs(y1 - y0))) + 1;
    for (int i = 0; i <= steps; ++i) {
        const double t = static_cast<double>(i) / steps;
        const int x = static_cast<int>(std::lround(x0 + t * (x1 - x0)));
        const int y = static_cast<int>(std::lround(y0 + t * (y1 - y0)));
        fill(img, x - 1, y - 1, x + 2, y + 2, c);
    }
}
} // namespace

std::array<uint8_t, 3> seriesColour(std::size_t i) {
    return kPalette[i % kPalette.size()];
}

std::string seriesColourHex(std::size_t i) {
    const auto c = seriesColour(i);
    char buf[8];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c[0], c[1], c[2]);
    return buf;
}

quality::RgbaImage errorMapImage(const quality::ScalarMap& error, uint32_t width, uint32_t height) {
    // A magma-like ramp through five stops.
    constexpr std::array<std::array<float, 3>, 5> stops{
        {{0, 0, 4}, {81, 18, 124}, {183, 55, 121}, {252, 137, 97}, {252, 253, 191}}};
    quality::RgbaImage img = canvas(width, height);
    for (std::size_t p = 0; p < img.count(); ++p) {
        const float t = std::clamp(error[p], 0.0f, 1.0f) * 4.0f;
        const auto i = std::min(static_cast<std::size_t>(t), std::size_t{3});
        const float f = t - static_cast<float>(i);
        for (std::size_t c = 0; c < 3; ++c) {
            img.pixels[4 * p + c] = static_cast<uint8_t>(
                std::lround(stops[i][c] + f * (stops[i + 1][c] - stops[i][c])));
        }
    }
    return img;
}

quality::RgbaImage bandBars(const std::vector<std::array<double, quality::kBands>>& series,
                            double maxValue) {
    constexpr int kW = 640, kH = 320, kMargin = 20, kGap = 24;
    quality::RgbaImage img = canvas(kW, kH);
    const int groupW = (kW - 2 * kMargin) / static_cast<int>(quality::kBands);
    const int barW =
        std::max(2, (groupW - kGap) / std::max<int>(1, static_cast<int>(series.size())));
    const int base = kH - kMargin;
    for (std::size_t b = 0; b < quality::kBands; ++b) {
        for (std::size_t s = 0; s < series.size(); ++s) {
            const double v = std::clamp(series[s][b] / std::max(maxValue, 1e-9), 0.0, 1.0);
            const int x0 =
                kMargin + static_cast<int>(b) * groupW + kGap / 2 + static_cast<int>(s) * barW;
            const int top = base - static_cast<int>(std::lround(v * (kH - 2 * kMargin)));
            fill(img, x0, top, x0 + barW - 1, base, seriesColour(s));
        }
    }
    fill(img, kMargin, base, kW - kMargin, base + 1, {0, 0, 0});
    return img;
}

quality::RgbaImage curvesImage(const std::vector<std::vector<std::pair<double, double>>>& series) {
    constexpr int kW = 640, kH = 400, kMargin = 30;
    quality::RgbaImage img = canvas(kW, kH);
    double x0 = 1e300, x1 = 0.0, y1 = 0.0;
    for (const auto& s : series) {
        for (const auto& [x, y] : s) {
            x0 = std::min(x0, x);
            x1 = std::max(x1, x);
            y1 = std::max(y1, y);
        }
    }
    if (x1 <= 0.0 || y1 <= 0.0) {
        return img;
    }
    const double lx0 = std::log(x0), lx1 = std::max(std::log(x1), lx0 + 1e-6);
    auto px = [&](double x) {
        return kMargin + (std::log(x) - lx0) / (lx1 - lx0) * (kW - 2 * kMargin);
    };
    auto py = [&](double y) { return kH - kMargin - y / (1.1 * y1) * (kH - 2 * kMargin); };
    fill(img, kMargin, kH - kMargin, kW - kMargin, kH - kMargin + 1, {0, 0, 0});
    fill(img, kMargin, kMargin, kMargin + 1, kH - kMargin, {0, 0, 0});
    for (std::size_t s = 0; s < series.size(); ++s) {
        for (std::size_t i = 0; i < series[s].size(); ++i) {
            const auto [x, y] = series[s][i];
            fill(img, static_cast<int>(px(x)) - 3, static_cast<int>(py(y)) - 3,
                 static_cast<int>(px(x)) + 4, static_cast<int>(py(y)) + 4, seriesColour(s));
            if (i > 0) {
                line(img, px(series[s][i - 1].first), py(series[s][i - 1].second), px(x), py(y),
                     seriesColour(s));
            }
        }
    }
    return img;
}

} // namespace gt::app
