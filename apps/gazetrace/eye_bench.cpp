// `gazetrace bench --suite eye`: pupil detection speed on one core (Google Benchmark), on
// pre-rendered 320x240 synthetic frames, clean, hard and wild; five repetitions each, reported as
// mean, median and spread.
#include <cstdio>
#include <utility>

#include <benchmark/benchmark.h>
#include <opencv2/core/utility.hpp>

#include "eye_commands.hpp"
#include "pupil/starburst_detector.hpp"
#include "sim/synthetic_eye.hpp"
#include "stop_request.hpp"

namespace gt::app {

nlohmann::json runEyeBench() {
    cv::setNumThreads(1); // one core, as the target says
    nlohmann::json result;
    const std::pair<const char*, eyetrack::EyeSimPreset> presets[] = {
        {"clean", eyetrack::EyeSimPreset::Clean},
        {"hard", eyetrack::EyeSimPreset::Hard},
        {"wild", eyetrack::EyeSimPreset::Wild}};
    for (const auto& [preset, look] : presets) {
        eyetrack::EyeSimConfig c;
        c.seed = 5;
        c.frames = 2400;
        eyetrack::applyPreset(c, look);
        const eyetrack::SyntheticEye eye(c);
        std::vector<cv::Mat> frames;
        for (int f = 0; f < c.frames; f += 10)
            frames.push_back(eye.render(f)); // all phases, blinks included
        const std::string name = std::string("pupil_detect/320x240/") + preset;
        benchmark::RegisterBenchmark(name.c_str(), [frames](benchmark::State& st) {
            throwIfStopRequested(); // once per run of the benchmark, outside its timed loop
            eyetrack::StarburstDetector detector;
            std::size_t i = 0;
            for (auto _ : st) {
                benchmark::DoNotOptimize(detector.detect(frames[i]));
                i = (i + 1) % frames.size();
            }
            st.counters["fps"] = benchmark::Counter(static_cast<double>(st.iterations()),
                                                    benchmark::Counter::kIsRate);
        })->Unit(benchmark::kMicrosecond);
    }
    // Five repetitions, reported with their median (the "median of 5 runs").
    int argc = 3;
    char arg0[] = "gazetrace";
    char arg1[] = "--benchmark_repetitions=5";
    char arg2[] = "--benchmark_report_aggregates_only=true";
    char* argv[] = {arg0, arg1, arg2, nullptr};
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::ClearRegisteredBenchmarks();
    return result;
}

} // namespace gt::app
