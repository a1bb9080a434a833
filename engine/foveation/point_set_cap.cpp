#include "foveation/point_set_cap.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "foveation/dart_throwing.hpp"

namespace gt::foveation {

namespace {

// Points per pixel of saturated random sequential adsorption with minimum distance p: 0.547 of
// the plane covered by discs of radius p/2 (Feder 1980), the densest a dart-throwing set gets.
double saturatedDensity(double p) {
    return 0.547 * 4.0 / (std::numbers::pi * p * p);
}

// Canvas points per canvas row (by whole-pixel row), their whole-pixel columns in row order.
struct RowBuckets {
    std::vector<uint32_t> start; // row r holds columns[start[r] .. start[r + 1])
    std::vector<uint16_t> columns;
};

RowBuckets bucketByRow(const PointSet& set) {
    const uint32_t rows = set.canvasHeight();
    RowBuckets b;
    b.start.assign(rows + 1, 0);
    for (const Point& p : set.points())
        ++b.start[static_cast<uint32_t>(p.y) + 1];
    for (uint32_t r = 0; r < rows; ++r)
        b.start[r + 1] += b.start[r];
    std::vector<uint32_t> fill(b.start.begin(), b.start.end() - 1);
    b.columns.resize(set.points().size());
    for (const Point& p : set.points())
        b.columns[fill[static_cast<uint32_t>(p.y)]++] = static_cast<uint16_t>(p.x);
    return b;
}

} // namespace

std::size_t screenPointCap(const DisplayProfile& display) noexcept {
    return static_cast<std::size_t>(display.width) * display.height;
}

TracedPoints maxPointsTraced(const PointSet& set, float margin) {
    // A point at canvas column x lands on screen column x + gx - W; with the margin m it is
    // traced when W - m - gx <= x < 2W + m - gx (x whole, gx whole): a window of W + 2m columns
    // starting at W - m - gx, and the same for rows.
    const auto w = static_cast<int64_t>(set.params().display.width);
    const auto h = static_cast<int64_t>(set.params().display.height);
    const auto m = static_cast<int64_t>(std::lround(margin));
    const RowBuckets rows = bucketByRow(set);
    std::vector<uint32_t> prefix(static_cast<std::size_t>(2 * w) + 1);
    std::vector<int64_t> sums(static_cast<std::size_t>(w) + 1, 0); // per gx, rows in the window
    // Adds (sign +1) or removes (-1) canvas row r's window counts for every gx.
    auto addRow = [&](int64_t r, int64_t sign) {
        if (r < 0 || r >= 2 * h) return;
        std::fill(prefix.begin(), prefix.end(), 0u);
        for (uint32_t i = rows.start[static_cast<std::size_t>(r)];
             i < rows.start[static_cast<std::size_t>(r) + 1]; ++i)
            ++prefix[rows.columns[i] + 1u];
        for (std::size_t c = 1; c < prefix.size(); ++c)
            prefix[c] += prefix[c - 1];
        for (int64_t gx = 0; gx <= w; ++gx) {
            const int64_t a = std::clamp<int64_t>(w - m - gx, 0, 2 * w);
            const int64_t b = std::clamp<int64_t>(2 * w + m - gx, 0, 2 * w);
            sums[static_cast<std::size_t>(gx)] +=
                sign * static_cast<int64_t>(prefix[static_cast<std::size_t>(b)] -
                                            prefix[static_cast<std::size_t>(a)]);
        }
    };
    // gy = H first (rows [-m, H + m)), then gy falling: the window's rows move one down.
    for (int64_t r = -m; r < h + m; ++r)
        addRow(r, +1);
    TracedPoints best;
    for (int64_t gy = h;; --gy) {
        for (int64_t gx = 0; gx <= w; ++gx) {
            const auto n = static_cast<std::size_t>(sums[static_cast<std::size_t>(gx)]);
            if (n > best.count) {
                best = {n, static_cast<uint32_t>(gx), static_cast<uint32_t>(gy)};
            }
        }
        if (gy == 0) break;
        const int64_t top = h - m - gy; // the window's first row for this gy
        addRow(top, -1);
        addRow(top + h + 2 * m, +1);
    }
    return best;
}

std::vector<double> spacingFloors(const PointSetParams& params, std::size_t cap) {
    constexpr int kFloors = 60; // 1.03^60 = 5.9: from the closed form to far sparser
    constexpr double kUnit = 1024.0;
    const DisplayProfile& d = params.display;
    const auto m = static_cast<int64_t>(std::lround(kSampleMargin));
    PointSetParams unfloored = params;
    unfloored.minSpacing = 0.0;
    const detail::SpacingTable spacing(unfloored);
    // The gaze at the screen centre: the window's pixels by whole distance from the centre of
    // interest, each with its spacing.
    const auto w = static_cast<int64_t>(d.width), h = static_cast<int64_t>(d.height);
    const int64_t gx = w / 2, gy = h / 2;
    std::vector<double> pixels;
    for (int64_t y = h - m - gy; y < 2 * h + m - gy; ++y) {
        for (int64_t x = w - m - gx; x < 2 * w + m - gx; ++x) {
            if (x < 0 || y < 0 || x >= 2 * w || y >= 2 * h) continue;
            const auto dist = static_cast<std::size_t>(
                std::hypot(static_cast<double>(x - w) + 0.5, static_cast<double>(y - h) + 0.5));
            if (dist >= pixels.size()) pixels.resize(dist + 1, 0.0);
            pixels[dist] += 1.0;
        }
    }
    auto predicted = [&](double floor) {
        double n = 0.0;
        for (std::size_t r = 0; r < pixels.size(); ++r) {
            const double p =
                std::max<double>(spacing.atDistance(static_cast<double>(r) + 0.5), floor);
            n += pixels[r] * saturatedDensity(p);
        }
        return n;
    };
    // Bisection between the centre's spacing and a floor that meets the cap everywhere.
    double lo = spacing.atDistance(0.0);
    double window = 0.0;
    for (const double n : pixels)
        window += n;
    double hi = std::max(lo, std::sqrt(saturatedDensity(1.0) * window / static_cast<double>(cap)));
    for (int i = 0; i < 50 && predicted(hi) > static_cast<double>(cap); ++i)
        hi *= 2.0;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (predicted(mid) > static_cast<double>(cap) ? lo : hi) = mid;
    }
    std::vector<double> floors;
    double f = std::max(hi, static_cast<double>(spacing.atDistance(0.0)) * 1.03);
    for (int i = 0; i < kFloors; ++i) {
        f = std::ceil(f * kUnit) / kUnit;
        floors.push_back(f);
        f *= 1.03;
    }
    return floors;
}

} // namespace gt::foveation
