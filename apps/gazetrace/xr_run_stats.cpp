#include "xr_run_stats.hpp"

#include <algorithm>
#include <cmath>

namespace gt::app {

namespace {

double medianOf(std::vector<double> v) {
    if (v.empty()) {
        return 0.0;
    }
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// The median of all but the first value: the first frame compiles pipelines and builds tables.
double steadyMedian(std::vector<double> v) {
    if (v.size() > 1) {
        v.erase(v.begin());
    }
    return medianOf(std::move(v));
}

} // namespace

nlohmann::json measuredMedian(std::vector<double> values) {
    if (values.empty()) {
        return nullptr;
    }
    return medianOf(std::move(values));
}

void RunStats::addFrame(const render::FrameResult& result, double renderMs) {
    mRenderMs.push_back(renderMs);
    for (const auto& v : result.views) {
        mRays += v.rays;
    }
    if (!result.timings) {
        return;
    }
    std::array<double, 2> eyeSum{0.0, 0.0};
    for (const rg::PassTiming& p : result.timings->passes) {
        mPassMs[p.name].push_back(p.gpuMs);
        for (std::size_t e = 0; e < 2; ++e) {
            if (p.name.starts_with(e == 0 ? "left." : "right.")) {
                eyeSum[e] += p.gpuMs;
            }
        }
    }
    mEyeGpuMs[0].push_back(eyeSum[0]);
    mEyeGpuMs[1].push_back(eyeSum[1]);
}

double RunStats::eyeGpuMs(std::size_t eye) const {
    return steadyMedian(mEyeGpuMs[eye]);
}

nlohmann::json RunStats::json() const {
    nlohmann::json passes = nlohmann::json::object();
    for (const auto& [name, times] : mPassMs) {
        passes[name] = steadyMedian(times);
    }
    // Per frame (both eyes), as `render` reports rays: the mean over the frames rendered.
    const auto frames = static_cast<double>(mRenderMs.size());
    const uint64_t perFrame =
        mRenderMs.empty()
            ? 0
            : static_cast<uint64_t>(std::llround(static_cast<double>(mRays) / frames));
    return {{"rays", perFrame},
            {"rays_total", mRays},
            {"gpu_ms", passes},
            {"frame_ms_median", steadyMedian(mFrameMs)},
            {"render_ms_median", steadyMedian(mRenderMs)},
            {"gaze_to_display_ms_median", measuredMedian(mGazeToDisplayMs)}};
}

} // namespace gt::app
