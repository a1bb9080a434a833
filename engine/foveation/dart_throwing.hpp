#pragma once
// What the two dart-throwing generators of PointSet share: the random numbers and the spacing
// p(x) of thesis eq. (4) as a function of the distance from the centre of interest.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "foveation/point_set.hpp"

namespace gt::foveation::detail {

// SplitMix64: a small, well-mixed, platform-independent generator (the set must be identical
// for a given seed everywhere, which std::uniform_real_distribution does not promise).
class SplitMix64 {
public:
    explicit SplitMix64(uint64_t seed) : mState(seed) {}
    uint64_t next() {
        uint64_t z = (mState += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }

private:
    uint64_t mState;
};

// Spacing as a function of distance, tabulated every 1/8 px (it depends on distance only) and
// never below the set's floor (PointSetParams::minSpacing).
class SpacingTable {
public:
    static constexpr double kStep = 0.125;

    explicit SpacingTable(const PointSetParams& params)
        : mCx(params.display.width), mCy(params.display.height) {
        const ContrastSensitivity csf;
        const double maxDist = std::hypot(mCx, mCy) + 2.0;
        mTable.resize(static_cast<std::size_t>(maxDist / kStep) + 2);
        for (std::size_t i = 0; i < mTable.size(); ++i) {
            const double p =
                csf.spacing(static_cast<double>(i) * kStep, params.display, params.scale);
            mTable[i] = static_cast<float>(std::max(p, params.minSpacing));
        }
    }

    [[nodiscard]] float maxSpacing() const {
        return *std::max_element(mTable.begin(), mTable.end());
    }

    // p at canvas position (x, y), interpolated between the tabulated distances.
    [[nodiscard]] float at(double x, double y) const {
        return atDistance(std::hypot(x - mCx, y - mCy));
    }
    [[nodiscard]] float atDistance(double distance) const {
        const double t = distance / kStep;
        const auto i = static_cast<std::size_t>(t);
        const auto f = static_cast<float>(t - static_cast<double>(i));
        return mTable[i] + f * (mTable[i + 1] - mTable[i]);
    }
    [[nodiscard]] double centreX() const { return mCx; }
    [[nodiscard]] double centreY() const { return mCy; }

private:
    double mCx, mCy;
    std::vector<float> mTable;
};

// The thesis's two series of darts (section 4.1): darts per pixel at canvas position (x, y).
[[nodiscard]] inline double dartsPerPixel(const PointSetParams& params, double x, double y) {
    const double sw = 0.8 * params.display.width, sh = 0.8 * params.display.height;
    const double cx = params.display.width, cy = params.display.height;
    const bool centre =
        x >= cx - 0.5 * sw && x < cx + 0.5 * sw && y >= cy - 0.5 * sh && y < cy + 0.5 * sh;
    return params.dartsPerCanvasPixel + (centre ? params.dartsPerCentrePixel : 0.0);
}

// The tiled generator (tiled_dart_throwing.cpp): the same acceptance rule, the darts spread over
// conflict-free tiles that `threads` threads fill in parallel; the output does not depend on
// the number of threads.
[[nodiscard]] std::vector<Point> throwDartsTiled(const PointSetParams& params,
                                                 const SpacingTable& spacing,
                                                 const PointSet::Progress& progress,
                                                 unsigned threads);

} // namespace gt::foveation::detail
