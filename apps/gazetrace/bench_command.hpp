#pragma once
// `gazetrace bench`: the thesis's tables and the headline comparison, measured with Google
// Benchmark (manual timing from GPU timestamps), printed and written as JSON.
#include <string>

#include <nlohmann/json.hpp>

namespace gt::app {

struct BenchOptions {
    std::string json;   // write the results here
    bool quick = false; // smoke test: fewer frames, no 32-ray frames
    std::string scene = "builtin:market";
    std::string cacheDir;
};

nlohmann::json runBench(const BenchOptions& options);

} // namespace gt::app
