#include "gaze/recording_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "error.hpp"
#include "formats/csv_tables.hpp"
#include "model/eye_model.hpp"
#include "model/eye_model_mapper.hpp"
#include "stats.hpp"

namespace gt::eyetrack {

namespace {

constexpr double kMinConfidence = 0.6;

// The component-wise median of unit vectors, normalised: a robust mean direction.
cv::Vec3d medianDirection(const std::vector<cv::Vec3d>& v) {
    std::vector<double> x, y, z;
    for (const cv::Vec3d& a : v) {
        x.push_back(a[0]);
        y.push_back(a[1]);
        z.push_back(a[2]);
    }
    return cv::normalize(cv::Vec3d(median(x), median(y), median(z)));
}

template <typename Observations>
void fit3d(EyeModel& model, const Observations& observations, const DisplayGeometry& display,
           CalibrationResult& result) {
    if (!model.fit())
        throw CalibrationError("3D calibration: the eye model could not be fitted (too few "
                               "confident pupils, or too little eye movement)");
    std::map<int, std::vector<cv::Vec3d>> perTarget;
    std::map<int, cv::Point2d> targetPos;
    for (const auto& o : observations) {
        if (o.target.phase != GazePhase::Calibration) continue;
        if (const auto axis = model.gaze(o.ellipse)) {
            perTarget[o.target.targetIndex].push_back(*axis);
            targetPos[o.target.targetIndex] = o.target.target;
        }
    }
    std::vector<cv::Vec3d> axes;
    std::vector<cv::Point2d> targets;
    for (const auto& [index, list] : perTarget) {
        axes.push_back(medianDirection(list));
        targets.push_back(targetPos[index]);
    }
    Model3dCalibration m;
    m.display = display;
    m.camera = model.camera();
    m.pupilRadiusMm = model.config().pupilRadiusMm;
    m.eyeCentreMm = model.centre();
    m.eyeRadiusMm = model.radius();
    m.fitRotation(axes, targets);
    // Validation, as for the polynomial.
    double errorSum = 0.0, precisionSum = 0.0;
    int samples = 0, precisionCount = 0, previousIndex = -1;
    cv::Point2d previousGaze;
    for (const auto& o : observations) {
        if (o.target.phase != GazePhase::Validation) continue;
        const auto axis = model.gaze(o.ellipse);
        const auto gaze = axis ? m.map(*axis) : std::nullopt;
        if (!gaze) continue;
        errorSum += display.angularDistanceDeg(*gaze, o.target.target);
        ++samples;
        if (previousIndex == o.target.targetIndex) {
            const double d = display.angularDistanceDeg(*gaze, previousGaze);
            precisionSum += d * d;
            ++precisionCount;
        }
        previousIndex = o.target.targetIndex;
        previousGaze = *gaze;
    }
    if (samples > 0) result.accuracy3dDeg = errorSum / samples;
    if (precisionCount > 0) result.precision3dDeg = std::sqrt(precisionSum / precisionCount);
    result.model3d = m;
}

} // namespace

TargetSchedule TargetSchedule::load(const std::filesystem::path& file) {
    const CsvTable t = CsvTable::load(file, {"t_ms", "target_x", "target_y"});
    // Every number finite and the times in order, named by line: a NaN or a row out of order
    // would otherwise put a target at the wrong time.
    t.requireNumbers({"phase", "note"});
    t.requireIncreasing("t_ms");
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
                                         PupilDetector& detector,
                                         const std::optional<CameraIntrinsics>& camera) {
    struct Observation {
        cv::Point2d pupil;
        ScheduledTarget target;
        cv::RotatedRect ellipse;
    };
    std::vector<Observation> observations;
    CalibrationResult result{};
    // The eye model sees every confident ellipse of the calibration phase, fixations and the
    // saccades between them alike (the more directions, the better the lines meet).
    std::optional<EyeModel> model;
    if (camera) {
        EyeModelConfig mc;
        mc.window = 1 << 20;
        mc.refitEvery = 1 << 30;
        model.emplace(*camera, mc);
    }
    while (auto frame = source.next()) {
        ++result.frames;
        const PupilResult pupil = detector.detect(frame->grey, frame->tMs);
        const auto now = schedule.at(frame->tMs);
        if (model && now && now->first.phase == GazePhase::Calibration && pupil.found &&
            pupil.confidence >= EyeModelMapper::kFitConfidence)
            model->add(pupil.ellipse);
        const auto target = schedule.at(frame->tMs);
        if (!target || target->first.phase == GazePhase::Free) continue;
        if (frame->tMs - target->second < settleMs) continue; // the eye is still on its way
        if (!pupil.found || pupil.confidence < kMinConfidence) continue;
        observations.push_back({pupil.centre(), target->first, pupil.ellipse});
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
    if (model) fit3d(*model, observations, display, result);
    return result;
}

} // namespace gt::eyetrack
