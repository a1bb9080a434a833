#include "demo_calibration.hpp"

#include <cstdlib>

#include "capture/file_sources.hpp"
#include "capture/frame_source.hpp"
#include "core/error.hpp"
#include "eye_source_parsing.hpp"
#include "pupil/starburst_detector.hpp"
#include "sim/synthetic_eye.hpp"

namespace gt::app {

namespace {
constexpr double kTargetMs = 1000.0; // per target, as eyesim's recordings
constexpr double kSettleMs = 400.0;  // after a target appears: saccade latency plus flight
constexpr double kFps = 120.0;       // the synthetic eye's camera

// synthetic:SEED[?...] -> SEED, or nullopt for any other source.
std::optional<std::uint64_t> syntheticSeed(const std::string& source) {
    if (source.rfind("synthetic:", 0) != 0) return std::nullopt;
    const std::string rest = source.substr(10, source.find('?') - 10);
    char* end = nullptr;
    const unsigned long long seed = std::strtoull(rest.c_str(), &end, 10);
    if (rest.empty() || *end != '\0') {
        throw ArgumentError("--gaze track:" + source + ": the seed must be a whole number");
    }
    return seed;
}
} // namespace

CalibrationSession::CalibrationSession(const std::string& gazeSpec, std::string out)
    : mOut(std::move(out)) {
    if (gazeSpec.rfind("track:", 0) != 0 || gazeSpec.size() <= 6) {
        throw ArgumentError("--calibrate needs --gaze track:SOURCE (the camera to calibrate)");
    }
    if (mOut.empty()) {
        throw ArgumentError("--calibrate needs --calibration FILE.json, where the result goes");
    }
    mSource = gazeSpec.substr(6);
    mConfig.calibrationPoints = 9;
    mConfig.validationPoints = 4;
    mConfig.targetMs = kTargetMs;
    mConfig.blinks = false;
    mDurationMs = (mConfig.calibrationPoints + mConfig.validationPoints) * kTargetMs;
    const std::optional<std::uint64_t> seed = syntheticSeed(mSource);
    mConfig.seed = seed.value_or(1);
    // The schedule as rows every 10 ms: what the window shows and what the fit matches.
    const eyetrack::GazeSchedule plan(mConfig, mDurationMs + 1000.0);
    std::vector<eyetrack::ScheduledTarget> rows;
    for (double t = 0.0; t <= mDurationMs + 500.0; t += 10.0) {
        const eyetrack::GazeState s = plan.at(t);
        rows.push_back({t, s.target, s.phase, s.targetIndex});
    }
    mSchedule = eyetrack::TargetSchedule::fromRows(std::move(rows));
    std::unique_ptr<eyetrack::FrameSource> source;
    if (seed) {
        eyetrack::EyeSimConfig c;
        eyetrack::applyPreset(c, eyetrack::EyeSimPreset::Clean);
        c.seed = *seed;
        c.fps = kFps;
        c.frames = static_cast<int>((mDurationMs + 500.0) * kFps / 1000.0);
        c.schedule = mConfig; // the demo's targets: the eye looks where they are shown
        source = std::make_unique<eyetrack::SyntheticSource>(c);
    } else {
        source = openFrameSource(mSource); // a camera or a recording
    }
    mWorker = std::jthread([this, src = std::move(source)]() mutable {
        try {
            eyetrack::StarburstDetector detector;
            mResult = eyetrack::calibrateFromRecording(*src, *mSchedule, mConfig.display, kSettleMs,
                                                       detector);
        } catch (const std::exception& e) {
            mError = e.what();
        }
    });
}

CalibrationSession::~CalibrationSession() = default; // the jthread joins

std::optional<glm::vec2> CalibrationSession::target(double tMs) const {
    if (tMs > mDurationMs) return std::nullopt;
    const auto t = mSchedule->at(tMs);
    if (!t || t->first.phase == eyetrack::GazePhase::Free) return std::nullopt;
    return glm::vec2(static_cast<float>(t->first.target.x), static_cast<float>(t->first.target.y));
}

nlohmann::json CalibrationSession::finish() {
    if (mWorker.joinable()) mWorker.join();
    if (!mError.empty()) throw Error("--calibrate with " + mSource + ": " + mError);
    const eyetrack::CalibrationResult& r = *mResult;
    r.calibration.save(mOut);
    return {{"calibration_targets", r.calibrationTargets},
            {"validation_targets", r.validationTargets},
            {"validation_samples", r.validationSamples},
            {"fit_error_deg", r.calibration.fitErrorDeg()},
            {"accuracy_deg", r.accuracyDeg},
            {"precision_deg", r.precisionDeg},
            {"camera_frames", r.frames},
            {"output", mOut}};
}

} // namespace gt::app
