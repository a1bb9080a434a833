#include "gaze/recording_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "error.hpp"
#include "io/csv_tables.hpp"
#include "stats.hpp"

namespace gt::eyetrack {

namespace {

constexpr double kMinConfidence = 0.6;

} // namespace

TargetSchedule TargetSchedule::load(const std::filesystem::path& file) {
    const CsvTable t = CsvTable::load(file, {"t_ms", "target_x", "target_y"});
    std::vector<ScheduledTarget> rows;
    int run = -1;
    cv::Point2d last(-1e30, -1e30);
    for (std::size_t i = 0; i < t.rows(); ++i) {
        ScheduledTarget r;
        r.tMs = t.number(i, "t_ms");
        r.target = {t.number(i, "target_x"), t.number(i, "target_y")};
        if (!std::isfinite(r.tMs) || !std::isfinite(r.target.x) || !std::isfinite(r.target.y))
            throw FormatError(file.string() + ": row " + std::to_string(i + 2) +
                              " has an empty time or target");
        try {
            r.phase =
                t.has("phase") ? gazePhaseFromString(t.text(i, "phase")) : GazePhase::Calibration;
        } catch (const FormatError& e) {
            throw FormatError(file.string() + ": row " + std::to_string(i + 2) + ": " + e.what());
        }
        if (t.has("target_index")) {
            r.targetIndex = static_cast<int>(t.number(i, "target_index"));
        } else {
            if (r.target != last) ++run;
            r.targetIndex = run;
        }
        last = r.target;
        rows.push_back(r);
    }
    if (rows.empty()) throw FormatError(file.string() + ": no target rows");
    return fromRows(std::move(rows));
}

TargetSchedule TargetSchedule::fromRows(std::vector<ScheduledTarget> rows) {
    TargetSchedule s;
    for (std::size_t i = 1; i < rows.size(); ++i)
        if (rows[i].tMs < rows[i - 1].tMs)
            throw FormatError("target schedule: times must not decrease");
    s.mRows = std::move(rows);
    for (std::size_t i = 0; i < s.mRows.size(); ++i) {
        const bool same = i > 0 && s.mRows[i].phase == s.mRows[i - 1].phase &&
                          s.mRows[i].targetIndex == s.mRows[i - 1].targetIndex &&
                          s.mRows[i].target == s.mRows[i - 1].target;
        s.mOnsetMs.push_back(same ? s.mOnsetMs.back() : s.mRows[i].tMs);
    }
    return s;
}

std::optional<std::pair<ScheduledTarget, double>> TargetSchedule::at(double tMs) const {
    auto it = std::upper_bound(mRows.begin(), mRows.end(), tMs + 1e-6,
                               [](double t, const ScheduledTarget& r) { return t < r.tMs; });
    if (it == mRows.begin()) return std::nullopt;
    const auto i = static_cast<std::size_t>(std::prev(it) - mRows.begin());
    return std::make_pair(mRows[i], mOnsetMs[i]);
}

CalibrationResult calibrateFromRecording(FrameSource& source, const TargetSchedule& schedule,
                                         const DisplayGeometry& display, double settleMs,
                                         PupilDetector& detector) {
    struct Observation {
        cv::Point2d pupil;
        ScheduledTarget target;
    };
    std::vector<Observation> observations;
    CalibrationResult result{Calibration{}, 0, 0, 0, 0.0, 0.0, 0};
    while (auto frame = source.next()) {
        ++result.frames;
        const PupilResult pupil = detector.detect(frame->grey);
        const auto target = schedule.at(frame->tMs);
        if (!target || target->first.phase == GazePhase::Free) continue;
        if (frame->tMs - target->second < settleMs) continue; // the eye is still on its way
        if (!pupil.found || pupil.confidence < kMinConfidence) continue;
        observations.push_back({pupil.centre(), target->first});
    }

    // Median pupil centre per calibration target.
    std::map<int, std::pair<std::vector<double>, std::vector<double>>> perTarget;
    std::map<int, cv::Point2d> targetPos;
    for (const auto& o : observations) {
        if (o.target.phase != GazePhase::Calibration) continue;
        perTarget[o.target.targetIndex].first.push_back(o.pupil.x);
        perTarget[o.target.targetIndex].second.push_back(o.pupil.y);
        targetPos[o.target.targetIndex] = o.target.target;
    }
    std::vector<CalibrationPoint> points;
    for (const auto& [index, xy] : perTarget)
        points.push_back({{median(xy.first), median(xy.second)}, targetPos[index]});
    result.calibrationTargets = static_cast<int>(points.size());
    result.calibration = Calibration::fit(points, display);

    // Validation targets: accuracy over all samples, precision from successive samples.
    double errorSum = 0.0, precisionSum = 0.0;
    int precisionCount = 0;
    std::map<int, int> seen;
    const Observation* previous = nullptr;
    cv::Point2d previousGaze;
    for (const auto& o : observations) {
        if (o.target.phase != GazePhase::Validation) continue;
        const cv::Point2d gaze = result.calibration.map(o.pupil);
        errorSum += display.angularDistanceDeg(gaze, o.target.target);
        ++result.validationSamples;
        ++seen[o.target.targetIndex];
        if (previous && previous->target.targetIndex == o.target.targetIndex) {
            const double d = display.angularDistanceDeg(gaze, previousGaze);
            precisionSum += d * d;
            ++precisionCount;
        }
        previous = &o;
        previousGaze = gaze;
    }
    result.validationTargets = static_cast<int>(seen.size());
    if (result.validationSamples > 0) result.accuracyDeg = errorSum / result.validationSamples;
    if (precisionCount > 0) result.precisionDeg = std::sqrt(precisionSum / precisionCount);
    return result;
}

} // namespace gt::eyetrack
