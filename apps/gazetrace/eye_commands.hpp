#pragma once
// The eye-tracker commands: `eyesim` (synthetic clips with truth), `track` (pupil + gaze from
// any frame source) and `calibrate` (fit the pupil-to-screen mapping from a recording).
#include <string>

#include <nlohmann/json.hpp>

#include "eye_camera_args.hpp"
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
    bool perspective = false;
    std::string intrinsicsOut; // the camera's intrinsics (JSON), for track/calibrate --model 3d
    std::string slipMm;        // X,Y,Z: headset slippage (camera frame, mm)
    double slipDeg = 0.0;
    double slipAtMs = -1.0;
    std::string eye = "cyclops"; // left | right | both (side by side); cyclops: one eye between
    double ipdMm = 63.0;
    double depthCm = 0.0;   // free viewing converges at this distance; 0: the screen
    std::string truthRight; // --eye both: the right eye's truth
};

struct TrackOptions {
    std::string source;
    std::string detector = "starburst";
    std::string calibration;
    std::string truth;
    std::string out;          // gaze CSV (t_ms,x,y)
    std::string pupils;       // per-frame pupil CSV
    std::string emit;         // udp://host:port
    std::string contactSheet; // PNG of every sheetEvery-th frame with its fitted pupil
    int sheetEvery = 25;
    int maxFrames = 0;        // 0: all
    std::string model = "2d"; // 2d | 3d
    std::string eye = "both"; // which eye of the calibration file
    EyeCameraArgs camera;     // --model 3d: replaces the calibration's intrinsics
    // Two eyes: a camera each, or one camera with two regions (--source and --regions).
    std::string sourceLeft, sourceRight, regions;
    std::string truthRight; // the right eye's truth (--truth is the left's)
    double ipdMm = 63.0;
    // The detector's history (last pupil, learnt size and shape) forgotten before every frame:
    // each frame judged as a single image, as a recording's first frame is.
    bool cold = false;
};

struct EyescoreOptions {
    std::string preset = "wild";
    std::string detector = "starburst";
    std::string seeds = "1-20";
    int frames = 300;
    int skip = 1560; // frames before the scored ones: past calibration and validation (13 s)
    double radiusPx = 5.0;
    double threshold = -1.0; // < 0: the gaze filter's default gate
    std::string misses;      // CSV of the wrong answers and the visible frames missed
    std::string missesSheet; // contact sheet (PNG) of every sheetEvery-th of those frames
    std::string answers;     // CSV of every answer with the evidence its confidence came from
    int sheetEvery = 20;
    bool cold = false; // the detector's history forgotten before every frame (TrackOptions::cold)
};

struct CalibrateOptions {
    std::string source;
    std::string detector = "starburst";
    std::string targets;
    std::string out;
    double settleMs = 300.0; // ignore the start of each target (saccade latency + flight)
    eyetrack::DisplayGeometry display;
    EyeCameraArgs camera;                         // given: the 3D eye model is calibrated too
    std::string sourceLeft, sourceRight, regions; // two eyes, as for track
};

struct SlippageOptions {
    std::string seeds = "1-8";
    std::string preset = "clean";
    std::string slipsMm = "1,2,3"; // slippage magnitudes
    double slipDeg = 2.0;
    std::string detector = "starburst";
};

nlohmann::json runEyesim(const EyesimOptions& options);
nlohmann::json runTrack(const TrackOptions& options);
nlohmann::json runTrackBinocular(const TrackOptions& options);
nlohmann::json runCalibrate(const CalibrateOptions& options);
nlohmann::json runEyeBench();
nlohmann::json runEyescore(const EyescoreOptions& options);
// --seeds N or A-B (A <= B, at most 10001 seeds); throws ArgumentError.
std::pair<std::uint64_t, std::uint64_t> parseSeedRange(const std::string& seeds);
nlohmann::json runSlippage(const SlippageOptions& options);

} // namespace gt::app
