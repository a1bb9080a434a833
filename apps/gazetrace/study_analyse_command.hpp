#pragma once
// `gazetrace study analyse JOURNAL...`: psychometric fits per participant and condition, group
// thresholds, a plot. `gazetrace study simulate --design FILE`: the design run by simulated
// observers with no rendering, to plan a study (how many trials, how well the threshold comes
// back) and to check the analysis on a threshold it was given.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gt::app {

struct StudyAnalyseOptions {
    std::vector<std::string> journals;
    std::string out = "out/study"; // thresholds.json, thresholds.csv, psychometric.png
    bool excludeFlagged = false;
    uint32_t bootstrap = 400;
    uint64_t seed = 1;
};

nlohmann::json runStudyAnalyse(const StudyAnalyseOptions& options);

struct StudySimulateOptions {
    std::string design;
    uint32_t observers = 100;
    double threshold = 0.0; // 0: the middle of each condition's grid
    double slope = 0.0;     // 0: a slope that spans a quarter of the grid
    double lapse = 0.02;
    std::string journals; // a folder: write each simulated participant's journal there
    std::string json;     // write the summary here too
    uint64_t seed = 1;
};

nlohmann::json runStudySimulate(const StudySimulateOptions& options);

} // namespace gt::app
