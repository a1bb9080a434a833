// `gazetrace slippage`: what headset slippage does to gaze accuracy, 2D polynomial against the 3D
// eye model. Per seed, an eyesim clip with a perspective camera is calibrated (both models, from
// its calibration targets) and validated (its validation targets); then the same eye and
// schedule are rendered with the headset moved by each slip (mm, in a seed-dependent direction)
// and turned by --slip-deg, and both calibrations — not redone — are validated again. The 3D
// model refits its eyeball on the slipped clip's own ellipses as it goes (its calibration phase
// runs first), which is how it would run in a headset; the polynomial has nothing to refit.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

#include <opencv2/core/utility.hpp>

#include "capture/file_sources.hpp"
#include "core/error.hpp"
#include "eye_commands.hpp"
#include "eye_source_parsing.hpp"
#include "gaze/gaze_mapper.hpp"
#include "gaze/recording_calibration.hpp"
#include "model/eye_model_mapper.hpp"
#include "pupil/pupil_detector.hpp"
#include "sim/synthetic_eye.hpp"
#include "stop_request.hpp"

namespace gt::app {

namespace {

constexpr double kSettleMs = 300.0;
constexpr int kFrames = 1600; // 9 calibration + 4 validation targets of 1 s at 120 Hz, and a bit

std::vector<double> parseList(const std::string& s, const char* flag) {
    std::vector<double> v;
    std::stringstream in(s);
    std::string item;
    while (std::getline(in, item, ',')) {
        char* end = nullptr;
        const double x = std::strtod(item.c_str(), &end);
        if (item.empty() || *end != '\0' || !std::isfinite(x) || x < 0.0 || x > 20.0) {
            throw ArgumentError(std::string(flag) + " " + s +
                                ": expected numbers 0..20, comma-separated");
        }
        v.push_back(x);
    }
    if (v.empty()) {
        throw ArgumentError(std::string(flag) + ": nothing given");
    }
    return v;
}

eyetrack::TargetSchedule scheduleOf(const eyetrack::SyntheticEye& eye) {
    std::vector<eyetrack::ScheduledTarget> rows;
    for (int f = 0; f < eye.config().frames; ++f) {
        const double t = eye.frameTimeMs(f);
        const eyetrack::GazeState g = eye.schedule().at(t);
        rows.push_back({t, g.target, g.phase, g.targetIndex});
    }
    return eyetrack::TargetSchedule::fromRows(std::move(rows));
}

// Mean angular error (degrees) on the validation targets after they settled.
double validate(const eyetrack::EyeSimConfig& c, eyetrack::GazeMapper& mapper,
                const std::string& detectorName) {
    eyetrack::SyntheticSource source(c);
    const auto schedule = scheduleOf(source.eye());
    const auto detector = eyetrack::makePupilDetector(pupilDetectorKind(detectorName));
    const eyetrack::DisplayGeometry& d = mapper.display();
    double sum = 0.0;
    int n = 0;
    while (auto frame = source.next()) {
        throwIfStopRequested();
        const eyetrack::PupilResult p = detector->detect(frame->grey, frame->tMs);
        // Every confident pupil goes through the mapper (the 3D model learns from it).
        const auto gaze = p.found ? mapper.map(p, frame->tMs) : std::nullopt;
        const auto target = schedule.at(frame->tMs);
        if (!target || target->first.phase != eyetrack::GazePhase::Validation) {
            continue;
        }
        if (frame->tMs - target->second < kSettleMs || !gaze || p.confidence < 0.6) {
            continue;
        }
        sum += d.angularDistanceDeg(*gaze, target->first.target);
        ++n;
    }
    if (n == 0) {
        throw Error("slippage: no validation samples (is the eye visible?)");
    }
    return sum / n;
}

} // namespace

nlohmann::json runSlippage(const SlippageOptions& o) {
    cv::setNumThreads(1);
    const auto [first, last] = parseSeedRange(o.seeds);
    const std::vector<double> slips = parseList(o.slipsMm, "--slips-mm");
    if (!std::isfinite(o.slipDeg) || std::abs(o.slipDeg) > 20.0) {
        throw ArgumentError("--slip-deg: expected a turn within 20 degrees");
    }
    (void)eyetrack::makePupilDetector(
        pupilDetectorKind(o.detector)); // a bad name fails before any work

    std::vector<double> before2d, before3d;
    std::vector<std::vector<double>> after2d(slips.size()), after3d(slips.size());
    for (std::uint64_t seed = first; seed <= last; ++seed) {
        throwIfStopRequested(); // calibrating one seed is a step of its own
        eyetrack::EyeSimConfig c;
        c.seed = seed;
        c.frames = kFrames;
        eyetrack::applyPreset(c, eyeSimPreset(o.preset));
        c.perspective = true;
        eyetrack::SyntheticSource source(c);
        const auto schedule = scheduleOf(source.eye());
        const auto detector = eyetrack::makePupilDetector(pupilDetectorKind(o.detector));
        const auto r = eyetrack::calibrateFromRecording(
            source, schedule, c.schedule.display, kSettleMs, *detector, source.eye().intrinsics());
        before2d.push_back(r.accuracyDeg);
        before3d.push_back(r.accuracy3dDeg);
        // The slip's direction turns with the seed; mostly sideways and vertical, some depth.
        const double a = 2.399963 * static_cast<double>(seed);
        const cv::Vec3d dir = cv::normalize(cv::Vec3d(std::cos(a), std::sin(a), 0.3));
        for (std::size_t i = 0; i < slips.size(); ++i) {
            eyetrack::EyeSimConfig moved = c;
            moved.slipMm = dir * slips[i];
            moved.slipDeg = o.slipDeg;
            moved.slipAtMs = 0.0;
            eyetrack::PolynomialMapper poly(r.calibration);
            eyetrack::EyeModelMapper model(*r.model3d);
            after2d[i].push_back(validate(moved, poly, o.detector));
            after3d[i].push_back(validate(moved, model, o.detector));
        }
    }
    auto mean = [](const std::vector<double>& v) {
        double s = 0.0;
        for (const double x : v) {
            s += x;
        }
        return v.empty() ? 0.0 : s / static_cast<double>(v.size());
    };
    auto worst = [](const std::vector<double>& v) {
        return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
    };
    nlohmann::json rows = nlohmann::json::array();
    for (std::size_t i = 0; i < slips.size(); ++i) {
        rows.push_back({{"slip_mm", slips[i]},
                        {"slip_deg", o.slipDeg},
                        {"accuracy_2d_deg", mean(after2d[i])},
                        {"accuracy_3d_deg", mean(after3d[i])},
                        {"worst_2d_deg", worst(after2d[i])},
                        {"worst_3d_deg", worst(after3d[i])}});
    }
    return {{"seeds", o.seeds},
            {"preset", o.preset},
            {"detector", o.detector},
            {"before_2d_deg", mean(before2d)},
            {"before_3d_deg", mean(before3d)},
            {"worst_before_3d_deg", worst(before3d)},
            {"after", rows}};
}

} // namespace gt::app
