#pragma once
// The figures of an `xr` run for its JSON summary, in the units every command's JSON uses
// (docs/json.md): rays per frame as `render` reports them (the run's sum as rays_total), and a
// gaze age only where one was measured (null for a source without a clock, such as `ahead`).
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "renderer.hpp"

namespace gt::app {

// The run's figures: per-pass and per-eye GPU times, wall times, rays and gaze ages.
class RunStats {
public:
    void addFrame(const render::FrameResult& result, double renderMs);
    void addInterval(double ms) { mFrameMs.push_back(ms); }
    void addGazeAge(double ms) { mGazeToDisplayMs.push_back(ms); }

    [[nodiscard]] uint64_t rays() const noexcept { return mRays; }
    [[nodiscard]] double eyeGpuMs(std::size_t eye) const;
    [[nodiscard]] nlohmann::json json() const;

private:
    std::vector<double> mFrameMs, mRenderMs, mGazeToDisplayMs;
    std::map<std::string, std::vector<double>> mPassMs;
    std::array<std::vector<double>, 2> mEyeGpuMs;
    uint64_t mRays = 0;
};

// The median, or null when nothing was measured (a 0 would read as a measured zero).
[[nodiscard]] nlohmann::json measuredMedian(std::vector<double> values);

} // namespace gt::app
