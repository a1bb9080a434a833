#include "eval_plots.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wconversion"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

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

constexpr std::array<uint8_t, 3> kBlack{0, 0, 0}, kGrey{200, 200, 200};

// Text in stb_easy_font's segments (about 6 x 12 pixels a character at scale 1), top-left at
// (x, y).
int textWidth(const std::string& t, int scale = 1) {
    std::string copy = t;
    return stb_easy_font_width(copy.data()) * scale;
}

void text(quality::RgbaImage& img, int x, int y, const std::string& t, std::array<uint8_t, 3> c,
          int scale = 1) {
    std::string copy = t;
    // A glyph is up to ~12 segments of one 64-byte quad each ("8", "B"): a smaller buffer makes
    // stb_easy_font stop mid-label and the last character is drawn in part.
    std::vector<char> quads(copy.size() * 1024 + 64);
    const int n = stb_easy_font_print(0.0f, 0.0f, copy.data(), nullptr, quads.data(),
                                      static_cast<int>(quads.size()));
    // Each quad: 4 vertices of x, y, z (float) and an RGBA colour (16 bytes), axis-aligned.
    for (int q = 0; q < n; ++q) {
        std::array<float, 2> lo{1e9f, 1e9f}, hi{-1e9f, -1e9f};
        for (int v = 0; v < 4; ++v) {
            float xy[2];
            std::memcpy(xy, quads.data() + (q * 4 + v) * 16, sizeof xy);
            for (int k = 0; k < 2; ++k) {
                lo[k] = std::min(lo[k], xy[k]);
                hi[k] = std::max(hi[k], xy[k]);
            }
        }
        fill(img, x + static_cast<int>(lo[0]) * scale, y + static_cast<int>(lo[1]) * scale,
             x + static_cast<int>(hi[0]) * scale, y + static_cast<int>(hi[1]) * scale, c);
    }
}

void textCentred(quality::RgbaImage& img, int cx, int y, const std::string& t,
                 std::array<uint8_t, 3> c, int scale = 1) {
    text(img, cx - textWidth(t, scale) / 2, y, t, c, scale);
}

std::string number(double v, const char* format) {
    char buf[32];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

// The smallest of 1, 2, 2.5, 5 times a power of ten at or above v.
double roundUp(double v) {
    if (!(v > 0.0)) return 1.0;
    const double p = std::pow(10.0, std::floor(std::log10(v)));
    for (const double m : {1.0, 2.0, 2.5, 5.0, 10.0}) {
        if (m * p >= v * (1.0 - 1e-9)) return m * p;
    }
    return 10.0 * p;
}

// The plot frame shared by the bars and the curves: title, data area, the value axis with its
// ticks, and the legend to the right of the area.
constexpr int kPlotW = 880, kPlotH = 430;
constexpr PlotBox kArea{80, 50, 640, 360};

PlotLayout frame(const std::vector<std::string>& names, double maxValue) {
    PlotLayout l;
    l.width = kPlotW;
    l.height = kPlotH;
    l.area = kArea;
    l.yMax = roundUp(maxValue);
    for (int i = 0; i <= 5; ++i)
        l.yTicks.push_back(l.yMax * i / 5.0);
    const int x = kArea.x1 + 24;
    for (std::size_t i = 0; i < names.size(); ++i) {
        const int y = kArea.y0 + 20 + static_cast<int>(i) * 22;
        l.legend.push_back({names[i],
                            seriesColour(i),
                            {x, y, x + 14, y + 14},
                            {x + 22, y + 1, x + 22 + textWidth(names[i]), y + 13}});
    }
    return l;
}

int yPixel(const PlotLayout& l, double v) {
    return l.area.y1 -
           static_cast<int>(std::lround(v / l.yMax * static_cast<double>(l.area.y1 - l.area.y0)));
}

void drawFrame(quality::RgbaImage& img, const PlotLayout& l, const std::string& title,
               const std::string& yTitle, const char* tickFormat) {
    textCentred(img, (l.area.x0 + l.area.x1) / 2, 12, title, kBlack, 2);
    text(img, 8, l.area.y0 - 20, yTitle, kBlack);
    for (const double t : l.yTicks) {
        const int y = yPixel(l, t);
        fill(img, l.area.x0 + 1, y, l.area.x1, y + 1, kGrey); // grid
        fill(img, l.area.x0 - 5, y, l.area.x0, y + 1, kBlack);
        const std::string s = number(t, tickFormat);
        text(img, l.area.x0 - 8 - textWidth(s), y - 5, s, kBlack);
    }
    fill(img, l.area.x0, l.area.y0, l.area.x0 + 1, l.area.y1 + 1, kBlack);
    fill(img, l.area.x0, l.area.y1, l.area.x1, l.area.y1 + 1, kBlack);
    for (const LegendEntry& e : l.legend) {
        fill(img, e.swatch.x0, e.swatch.y0, e.swatch.x1, e.swatch.y1, e.colour);
        text(img, e.label.x0, e.label.y0, e.name, kBlack);
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

std::vector<std::string> seriesNames(const nlohmann::json& plotSeries) {
    std::vector<std::string> names;
    for (const auto& s : plotSeries)
        names.push_back(s.at("name").get<std::string>());
    return names;
}

PlotLayout bandBarsLayout(const std::vector<std::string>& names, double maxValue) {
    return frame(names, maxValue);
}

quality::RgbaImage bandBars(const std::vector<std::array<double, quality::kBands>>& series,
                            double maxValue, const std::vector<std::string>& names) {
    const PlotLayout l = bandBarsLayout(names, maxValue);
    quality::RgbaImage img =
        canvas(static_cast<uint32_t>(l.width), static_cast<uint32_t>(l.height));
    drawFrame(img, l, "FLIP per eccentricity band (lower is better)", "FLIP (0..1)", "%.3g");
    constexpr int kGap = 20;
    const int groupW = (l.area.x1 - l.area.x0) / static_cast<int>(quality::kBands);
    const int barW =
        std::max(2, (groupW - kGap) / std::max<int>(1, static_cast<int>(series.size())));
    for (std::size_t b = 0; b < quality::kBands; ++b) {
        const int g0 = l.area.x0 + static_cast<int>(b) * groupW;
        for (std::size_t s = 0; s < series.size(); ++s) {
            const double v = std::clamp(series[s][b], 0.0, l.yMax);
            const int x0 = g0 + kGap / 2 + static_cast<int>(s) * barW;
            const int top = yPixel(l, v);
            fill(img, x0, top, x0 + barW - 1, l.area.y1, seriesColour(s));
            textCentred(img, x0 + barW / 2, top - 12, number(series[s][b], "%.3f"), kBlack);
        }
        textCentred(img, g0 + groupW / 2, l.area.y1 + 8,
                    std::string(quality::kBandNames[b]) + " deg", kBlack);
    }
    textCentred(img, (l.area.x0 + l.area.x1) / 2, l.area.y1 + 30,
                "eccentricity band: degrees from the gaze", kBlack);
    return img;
}

PlotLayout curvesLayout(const std::vector<std::string>& names, double maxValue) {
    return frame(names, maxValue * 1.1);
}

namespace {
// "12k", "1.5M": the rays axis's ticks.
std::string raysText(double v) {
    if (v >= 1e6) return number(v / 1e6, "%.3gM");
    if (v >= 1e3) return number(v / 1e3, "%.3gk");
    return number(v, "%.3g");
}
} // namespace

quality::RgbaImage curvesImage(const std::vector<std::vector<std::pair<double, double>>>& series,
                               const std::vector<std::string>& names, const CurveAxes& axes) {
    double x0 = 1e300, x1 = 0.0, y1 = 0.0;
    for (const auto& s : series) {
        for (const auto& [x, y] : s) {
            x0 = std::min(x0, x);
            x1 = std::max(x1, x);
            y1 = std::max(y1, y);
        }
    }
    const PlotLayout l = curvesLayout(names, y1);
    quality::RgbaImage img =
        canvas(static_cast<uint32_t>(l.width), static_cast<uint32_t>(l.height));
    drawFrame(img, l, axes.title, axes.yTitle, "%.3g");
    textCentred(img, (l.area.x0 + l.area.x1) / 2, l.area.y1 + 30, axes.xTitle, kBlack);
    if (x1 <= 0.0 || y1 <= 0.0) {
        return img;
    }
    // A margin of a tenth of the span each side, so the end points are not on the axes.
    const double span = std::max(std::log(x1) - std::log(x0), 1e-3);
    const double lx0 = std::log(x0) - 0.1 * span, lx1 = std::log(x1) + 0.1 * span;
    auto px = [&](double x) {
        return l.area.x0 + (std::log(x) - lx0) / (lx1 - lx0) * (l.area.x1 - l.area.x0);
    };
    auto py = [&](double y) { return static_cast<double>(yPixel(l, y)); };
    auto tick = [&](double v) {
        const int x = static_cast<int>(std::lround(px(v)));
        fill(img, x, l.area.y1, x + 1, l.area.y1 + 5, kBlack);
        textCentred(img, x, l.area.y1 + 8, raysText(v), kBlack);
    };
    if (axes.ticksAtData) {
        for (const auto& s : series) {
            for (const auto& point : s)
                tick(point.first);
        }
    } else {
        // Ticks at 1, 2 and 5 times the powers of ten inside the axis.
        for (double p = std::pow(10.0, std::floor(lx0 / std::log(10.0))); p < std::exp(lx1);
             p *= 10) {
            for (const double m : {1.0, 2.0, 5.0}) {
                const double v = m * p;
                if (std::log(v) < lx0 || std::log(v) > lx1) continue;
                tick(v);
            }
        }
    }
    for (std::size_t s = 0; s < series.size(); ++s) {
        for (std::size_t i = 0; i < series[s].size(); ++i) {
            const auto [x, y] = series[s][i];
            fill(img, static_cast<int>(px(x)) - 3, static_cast<int>(py(y)) - 3,
                 static_cast<int>(px(x)) + 4, static_cast<int>(py(y)) + 4, seriesColour(s));
            if (i > 0) {
                line(img, px(series[s][i - 1].first), py(series[s][i - 1].second), px(x), py(y),
                     seriesColour(s));
            }
            text(img, static_cast<int>(px(x)) + 6, static_cast<int>(py(y)) - 14,
                 number(y, axes.valueFormat.c_str()), seriesColour(s));
        }
    }
    return img;
}

namespace {

constexpr int kLegendRows = 12; // more participants than this are summed up in one line

void disc(quality::RgbaImage& img, double cx, double cy, double r, std::array<uint8_t, 3> c) {
    const int x0 = static_cast<int>(std::floor(cx - r)), x1 = static_cast<int>(std::ceil(cx + r));
    const int y0 = static_cast<int>(std::floor(cy - r)), y1 = static_cast<int>(std::ceil(cy + r));
    for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
            if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r) put(img, x, y, c);
        }
    }
}

quality::RgbaImage psychometricPanel(const PsychometricPanel& panel) {
    std::vector<std::string> names;
    for (std::size_t i = 0; i < panel.series.size() && i < kLegendRows; ++i)
        names.push_back(panel.series[i].name);
    if (panel.series.size() > kLegendRows) {
        names.push_back("+" + std::to_string(panel.series.size() - kLegendRows) + " more");
    }
    PlotLayout l = frame(names, 1.0);
    if (panel.series.size() > kLegendRows) l.legend.back().colour = {255, 255, 255};
    quality::RgbaImage img =
        canvas(static_cast<uint32_t>(l.width), static_cast<uint32_t>(l.height));
    // A margin of a twentieth of the span each side, so the end levels are not on the axes.
    const double span = std::max(panel.xMax - panel.xMin, 1e-12);
    const double x0 = panel.xMin - 0.05 * span, x1 = panel.xMax + 0.05 * span;
    auto px = [&](double x) {
        return l.area.x0 + (x - x0) / (x1 - x0) * static_cast<double>(l.area.x1 - l.area.x0);
    };
    auto py = [&](double y) { return static_cast<double>(yPixel(l, y)); };
    if (panel.group) {
        const auto& [mean, low, high] = *panel.group;
        fill(img, static_cast<int>(px(low)), l.area.y0, static_cast<int>(px(high)) + 1, l.area.y1,
             {225, 225, 225});
    }
    drawFrame(img, l, panel.title, "proportion positive", "%.1f");
    textCentred(img, (l.area.x0 + l.area.x1) / 2, l.area.y1 + 30, panel.xTitle, kBlack);
    const double tickStep = roundUp(span / 6.0);
    for (double v = std::ceil(panel.xMin / tickStep - 1e-9) * tickStep;
         v <= panel.xMax + 1e-9 * span; v += tickStep) {
        const int x = static_cast<int>(std::lround(px(v)));
        fill(img, x, l.area.y1, x + 1, l.area.y1 + 5, kBlack);
        textCentred(img, x, l.area.y1 + 8, number(v, "%.4g"), kBlack);
    }
    for (std::size_t s = 0; s < panel.series.size(); ++s) {
        const PsychometricSeries& series = panel.series[s];
        const auto colour = seriesColour(s);
        for (std::size_t i = 1; i < series.curve.size(); ++i) {
            line(img, px(series.curve[i - 1].first), py(series.curve[i - 1].second),
                 px(series.curve[i].first), py(series.curve[i].second), colour);
        }
        for (const auto& [level, proportion, trials] : series.points)
            disc(img, px(level), py(proportion), std::min(10.0, 1.5 + std::sqrt(trials)), colour);
    }
    if (panel.group) {
        const auto& [mean, low, high] = *panel.group;
        const int x = static_cast<int>(std::lround(px(mean)));
        fill(img, x - 1, l.area.y0, x + 2, l.area.y1, kBlack);
        text(img, l.area.x0 + 6, l.area.y0 + 4,
             "group threshold " + number(mean, "%.4g") + "  95% [" + number(low, "%.4g") + ", " +
                 number(high, "%.4g") + "]",
             kBlack);
    }
    return img;
}

} // namespace

quality::RgbaImage psychometricImage(const std::vector<PsychometricPanel>& panels) {
    std::vector<quality::RgbaImage> parts;
    for (const PsychometricPanel& panel : panels)
        parts.push_back(psychometricPanel(panel));
    if (parts.empty()) parts.push_back(canvas(kPlotW, kPlotH));
    quality::RgbaImage img = canvas(kPlotW, static_cast<uint32_t>(kPlotH * parts.size()));
    std::size_t offset = 0;
    for (const quality::RgbaImage& part : parts) {
        std::copy(part.pixels.begin(), part.pixels.end(), img.pixels.begin() + offset);
        offset += part.pixels.size();
    }
    return img;
}

} // namespace gt::app
