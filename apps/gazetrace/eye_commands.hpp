#pragma once
// The eye-tracker commands: `eyesim` (synthetic clips with truth), `track` (pupil + gaze from
// any frame source) and `calibrate` (fit the pupil-to-screen mapping from a recording).
#include <string>

#include <nlohmann/json.hpp>

#include "gaze/display_geometry.hpp"

namespace gt::app {

struct EyesimOptions {
    std::uint64_t seed = 1;
    int frames = 600;
    std::string size = "320x240";
    double fps = 120.0;
    std::string preset = "clean";
    int grid = 9;
    double targetMs = 1000.0;
    std::string out;   // video (.mkv / .avi, lossless FFV1)
    std::string truth; // CSV
};

struct TrackOptions {
    std::string source;
    std::string calibration;
    std::string truth;
    std::string out;          // gaze CSV (t_ms,x,y)
    std::string pupils;       // per-frame pupil CSV
    std::string emit;         // udp://host:port
    std::string contactSheet; // PNG of every sheetEvery-th frame with its fitted pupil
    int sheetEvery = 25;
    int maxFrames = 0; // 0: all
};

struct CalibrateOptions {
    std::string source;
    std::string targets;
    std::string out;
    double settleMs = 300.0; // ignore the start of each target (saccade latency + flight)
    eyetrack::DisplayGeometry display;
};

nlohmann::json runEyesim(const EyesimOptions& options);
nlohmann::json runTrack(const TrackOptions& options);
nlohmann::json runCalibrate(const CalibrateOptions& options);
nlohmann::json runEyeBench();

} // namespace gt::app
