#include "sim/gaze_schedule.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "error.hpp"

namespace gt::eyetrack {

namespace {

// Minimum-jerk position profile (Flash & Hogan 1985): smooth start and landing, like a saccade's
// velocity bell.
double minimumJerk(double u) {
    u = std::clamp(u, 0.0, 1.0);
    return u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);
}

double smoothstep(double u) {
    u = std::clamp(u, 0.0, 1.0);
    return u * u * (3.0 - 2.0 * u);
}

// Saccade duration from its amplitude, the main sequence (Carpenter 1988).
double saccadeDurationMs(double amplitudeDeg) {
    return amplitudeDeg < 0.05 ? 0.0 : 2.2 * amplitudeDeg + 21.0;
}

cv::Point2d lerp(cv::Point2d a, cv::Point2d b, double u) {
    return a + (b - a) * u;
}

} // namespace

const char* toString(GazePhase phase) noexcept {
    switch (phase) {
    case GazePhase::Calibration:
        return "calibration";
    case GazePhase::Validation:
        return "validation";
    case GazePhase::Free:
        return "free";
    }
    return "free";
}

GazePhase gazePhaseFromString(const std::string& s) {
    if (s == "calibration") return GazePhase::Calibration;
    if (s == "validation") return GazePhase::Validation;
    if (s == "free") return GazePhase::Free;
    throw FormatError("unknown phase '" + s + "' (calibration | validation | free)");
}

std::vector<cv::Point2d> calibrationGrid(int n, const DisplayGeometry& d) {
    const double w = d.widthPx, h = d.heightPx;
    auto at = [&](double fx, double fy) { return cv::Point2d(fx * w, fy * h); };
    std::vector<cv::Point2d> grid;
    if (n == 5) {
        grid = {at(0.5, 0.5), at(0.1, 0.1), at(0.9, 0.1), at(0.1, 0.9), at(0.9, 0.9)};
    } else if (n == 9 || n == 13) {
        for (double fy : {0.1, 0.5, 0.9})
            for (double fx : {0.1, 0.5, 0.9})
                grid.push_back(at(fx, fy));
        if (n == 13) {
            for (double fy : {0.3, 0.7})
                for (double fx : {0.3, 0.7})
                    grid.push_back(at(fx, fy));
        }
    } else {
        throw CalibrationError("calibration grid must have 5, 9 or 13 points, not " +
                               std::to_string(n));
    }
    return grid;
}

std::vector<cv::Point2d> validationTargets(int n, const DisplayGeometry& d,
                                           const std::vector<cv::Point2d>& grid) {
    const double w = d.widthPx, h = d.heightPx;
    std::vector<cv::Point2d> all = {
        {0.3 * w, 0.3 * h}, {0.7 * w, 0.7 * h}, {0.7 * w, 0.3 * h}, {0.3 * w, 0.7 * h},
        {0.5 * w, 0.2 * h}, {0.5 * w, 0.8 * h}, {0.2 * w, 0.5 * h}, {0.8 * w, 0.5 * h},
    };
    // Never validate on a point the calibration was fitted on.
    std::erase_if(
        all, [&](cv::Point2d p) { return std::find(grid.begin(), grid.end(), p) != grid.end(); });
    const auto count = static_cast<std::size_t>(std::clamp(n, 0, static_cast<int>(all.size())));
    return {all.begin(), all.begin() + static_cast<std::ptrdiff_t>(count)};
}

GazeSchedule::GazeSchedule(const ScheduleConfig& config, double durationMs) : mConfig(config) {
    std::mt19937_64 rng(config.seed * 0x9E3779B97F4A7C15ull + 17);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    const DisplayGeometry& d = config.display;
    const cv::Point2d centre(0.5 * d.widthPx, 0.5 * d.heightPx);
    double t = 0.0;
    auto fixate = [&](cv::Point2d p, double ms, GazePhase phase, int index) {
        Segment s;
        s.startMs = t;
        s.endMs = t + ms;
        s.from = s.to = p;
        s.phase = phase;
        s.targetIndex = index;
        addSegment(s);
        t += ms;
    };

    const auto grid = calibrationGrid(config.calibrationPoints, d);
    for (std::size_t i = 0; i < grid.size() && t < durationMs; ++i)
        fixate(grid[i], config.targetMs, GazePhase::Calibration, static_cast<int>(i));
    const auto valid = validationTargets(config.validationPoints, d, grid);
    for (std::size_t i = 0; i < valid.size() && t < durationMs; ++i)
        fixate(valid[i], config.targetMs, GazePhase::Validation, static_cast<int>(i));
    const double freeStart = t;

    cv::Point2d last = mSegments.empty() ? centre : mSegments.back().to;
    while (t < durationMs) {
        // One draw per statement: a constructor's arguments are evaluated in an unspecified
        // order (GCC right to left, clang left to right), and two draws among them made the
        // clips differ between compilers. y is drawn first, as GCC did, so the clips every
        // reported number was measured on stay the same.
        const double fy = 0.05 + 0.9 * uni(rng);
        const double fx = 0.05 + 0.9 * uni(rng);
        const cv::Point2d p(d.widthPx * fx, d.heightPx * fy);
        if (uni(rng) < 0.3) {
            // Smooth pursuit: the target glides from the current point towards p at 5-15 deg/s.
            const double speed = 5.0 + 10.0 * uni(rng);
            const double ms = 800.0 + 800.0 * uni(rng);
            const double wantDeg = speed * ms / 1000.0;
            const double haveDeg = std::max(d.angularDistanceDeg(last, p), 1e-3);
            Segment s;
            s.startMs = t;
            s.endMs = t + ms;
            s.from = last;
            s.to = lerp(last, p, std::min(1.0, wantDeg / haveDeg));
            addSegment(s);
            t += ms;
            last = s.to;
        } else {
            fixate(p, 250.0 + 450.0 * uni(rng), GazePhase::Free, -1);
            last = p;
        }
    }
    if (config.blinks) {
        for (double b = freeStart + 800.0 + 1500.0 * uni(rng); b < durationMs;
             b += 2000.0 + 3000.0 * uni(rng))
            mBlinks.push_back({b, 100.0 + 200.0 * uni(rng)});
    }
}

void GazeSchedule::addSegment(Segment s) {
    const DisplayGeometry& d = mConfig.display;
    s.eyeStart = mSegments.empty() ? cv::Point2d(0.5 * d.widthPx, 0.5 * d.heightPx)
                                   : eyeAt(mSegments.back(), mSegments.back().endMs);
    // Aim where the target will be when the saccade lands (pursuit targets move meanwhile).
    const double latency = mConfig.saccadeLatencyMs;
    double dur =
        saccadeDurationMs(d.angularDistanceDeg(s.eyeStart, targetAt(s, s.startMs + latency)));
    for (int i = 0; i < 2; ++i) {
        s.saccadeTo = targetAt(s, s.startMs + latency + dur);
        dur = saccadeDurationMs(d.angularDistanceDeg(s.eyeStart, s.saccadeTo));
    }
    s.saccadeTo = targetAt(s, s.startMs + latency + dur);
    s.saccadeMs = dur;
    mSegments.push_back(s);
}

cv::Point2d GazeSchedule::targetAt(const Segment& s, double tMs) const {
    const double len = s.endMs - s.startMs;
    return len <= 0.0 ? s.to : lerp(s.from, s.to, std::clamp((tMs - s.startMs) / len, 0.0, 1.0));
}

cv::Point2d GazeSchedule::eyeAt(const Segment& s, double tMs) const {
    const double onset = s.startMs + mConfig.saccadeLatencyMs;
    if (tMs < onset) return s.eyeStart;
    if (tMs < onset + s.saccadeMs)
        return lerp(s.eyeStart, s.saccadeTo, minimumJerk((tMs - onset) / s.saccadeMs));
    return targetAt(s, tMs); // fixation: the target; pursuit: on the moving target
}

GazeState GazeSchedule::at(double tMs) const {
    GazeState g;
    if (mSegments.empty()) return g;
    auto it = std::upper_bound(mSegments.begin(), mSegments.end(), tMs,
                               [](double t, const Segment& s) { return t < s.startMs; });
    const Segment& s = it == mSegments.begin() ? mSegments.front() : *std::prev(it);
    g.target = targetAt(s, tMs);
    g.phase = s.phase;
    g.targetIndex = s.targetIndex;

    // Fixational tremor and drift: a few incommensurate sinusoids, deterministic in t and seed.
    const double ppd = mConfig.display.pixelsPerDegreeAtCentre();
    const double ph = static_cast<double>(mConfig.seed % 1000) * 0.731;
    const double ts = tMs / 1000.0, twoPi = 2.0 * std::numbers::pi;
    const double tx = std::sin(twoPi * 3.1 * ts + ph) + 0.7 * std::sin(twoPi * 7.3 * ts + 2.0 * ph);
    const double ty = std::sin(twoPi * 2.7 * ts + 3.0 * ph) + 0.7 * std::sin(twoPi * 6.1 * ts + ph);
    g.gaze = eyeAt(s, tMs) + cv::Point2d(tx, ty) * (mConfig.tremorDeg * ppd / 1.22);

    for (const Blink& b : mBlinks) {
        if (tMs < b.startMs || tMs > b.startMs + b.durationMs) continue;
        // Lids close fast (35 %), stay shut briefly, reopen more slowly.
        const double u = (tMs - b.startMs) / b.durationMs;
        const double closed = u < 0.35  ? smoothstep(u / 0.35)
                              : u < 0.5 ? 1.0
                                        : 1.0 - smoothstep((u - 0.5) / 0.5);
        g.lidOpen = 1.0 - closed;
    }
    return g;
}

} // namespace gt::eyetrack
