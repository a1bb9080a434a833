#pragma once
// `gazetrace bench`: the thesis's tables and the headline comparison, measured with Google
// Benchmark (manual timing from GPU timestamps), printed and written as JSON.
#include <string>

#include <nlohmann/json.hpp>

#include "integrator_args.hpp"

namespace gt::app {

struct BenchOptions {
    std::string json;   // write the results here
    bool quick = false; // smoke test: fewer frames, no 32-ray frames
    std::string scene = "builtin:market";
    std::string cacheDir;
    std::string hmd = "fove"; // --suite stereo: the headset whose eyes are measured
    // --suite stereo and scale: the light transport of the headset frames' reference and point
    // sets (the layers trace direct light).
    IntegratorArgs integrator;
};

nlohmann::json runBench(const BenchOptions& options);
// --suite stereo: the HMD frame (both eyes of --hmd) and the desktop demo's frame, one frame in
// flight against two (apps/gazetrace/stereo_bench.cpp).
nlohmann::json runStereoBench(const BenchOptions& options);
// Eccentricity layers only (Guenter et al. 2012): the predictions and the measured ratios against
// the reference, also part of the full `render` suite.
nlohmann::json runLayersBench(const BenchOptions& options);
// --suite animation: the CPU cost per frame of a built scene that moves (pose, skinning,
// bottom-level refits and rebuilds, the top level) and refitting's cost to tracing
// (apps/gazetrace/bench_animation.cpp).
nlohmann::json runAnimationBench(const BenchOptions& options);
// Writes `j` to `path` through a temporary file renamed when complete.
void writeJsonFile(const std::string& path, const nlohmann::json& j);

} // namespace gt::app
