#pragma once
// What the synthetic viewer looks at, and where the eye actually points, over time.
//
// The target schedule has three phases, so a synthetic clip is also a calibration recording:
//  - calibration: a grid of targets (3x3 by default; 5 and 13 points too), one fixation each;
//  - validation: targets between the grid points, never used for fitting;
//  - free viewing: random fixations, smooth pursuit of moving targets, and blinks.
// The eye follows with human dynamics: a saccade latency, saccades whose duration follows the
// main sequence (D = 2.2 ms/deg * A + 21 ms, Carpenter 1988) with a minimum-jerk profile, pursuit
// that matches the target's velocity after a catch-up saccade, and fixational tremor.
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core/types.hpp>

#include "gaze/display_geometry.hpp"

namespace gt::eyetrack {

enum class GazePhase { Calibration, Validation, Free };
[[nodiscard]] const char* toString(GazePhase phase) noexcept;
[[nodiscard]] GazePhase gazePhaseFromString(const std::string& s); // throws FormatError

struct ScheduleConfig {
    DisplayGeometry display;
    int calibrationPoints = 9; // 5, 9 or 13
    int validationPoints = 4;
    double targetMs = 1000.0; // fixation time per calibration / validation target
    double saccadeLatencyMs = 150.0;
    bool blinks = true;      // blinks in the free-viewing phase
    double tremorDeg = 0.03; // fixational tremor, RMS per axis
    std::uint64_t seed = 1;
};

struct GazeState {
    cv::Point2d target; // screen pixels: where the target is
    cv::Point2d gaze;   // screen pixels: where the eye points (follows the target)
    GazePhase phase = GazePhase::Free;
    int targetIndex = -1; // calibration / validation target number, -1 in free viewing
    double lidOpen = 1.0; // 1 open, 0 closed (blink)
};

// Screen positions of an n-point calibration grid (5: centre and corners; 9: 3x3; 13: 3x3 plus
// the four inner diagonal points) at 10 % / 50 % / 90 % of the screen.
[[nodiscard]] std::vector<cv::Point2d> calibrationGrid(int n, const DisplayGeometry& d);
// Validation targets placed between the grid points (30 % / 70 %, then the edge midpoints),
// leaving out any point of `grid`.
[[nodiscard]] std::vector<cv::Point2d> validationTargets(int n, const DisplayGeometry& d,
                                                         const std::vector<cv::Point2d>& grid);

class GazeSchedule {
public:
    // Plans enough segments to cover durationMs.
    GazeSchedule(const ScheduleConfig& config, double durationMs);

    [[nodiscard]] GazeState at(double tMs) const;
    [[nodiscard]] const ScheduleConfig& config() const noexcept { return mConfig; }

private:
    struct Segment {
        double startMs = 0.0, endMs = 0.0;
        cv::Point2d from, to;   // target motion: from -> to over the segment (equal: fixation)
        cv::Point2d eyeStart;   // where the eye is when the segment starts
        cv::Point2d saccadeTo;  // where the first saccade lands
        double saccadeMs = 0.0; // its duration (main sequence)
        GazePhase phase = GazePhase::Free;
        int targetIndex = -1;
    };
    struct Blink {
        double startMs, durationMs;
    };

    [[nodiscard]] cv::Point2d targetAt(const Segment& s, double tMs) const;
    [[nodiscard]] cv::Point2d eyeAt(const Segment& s, double tMs) const;
    void addSegment(Segment s);

    ScheduleConfig mConfig;
    std::vector<Segment> mSegments;
    std::vector<Blink> mBlinks;
};

} // namespace gt::eyetrack
