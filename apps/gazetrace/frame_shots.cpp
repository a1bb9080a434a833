#include "frame_shots.hpp"

#include <span>

#include "stop_request.hpp"

namespace gt::app {

std::vector<uint8_t> FrameShots::shot(render::View v, render::FoveationMethod& m, uint64_t* rays) {
    throwIfStopRequested(); // the quality sweeps are fixed-length runs, shot by shot
    v.method = &m;
    v.exposure = mRenderer.scene().exposure;
    render::OutputTarget* const target = &mReadback;
    const render::FrameResult f = mRenderer.renderFrame(std::span(&v, 1), std::span(&target, 1));
    if (rays) {
        *rays = f.views.front().rays;
    }
    mLast = f.timings.value_or(rg::FrameTimings{});
    return mReadback.takePixels();
}

double FrameShots::lastPassMs(const std::string& part) const {
    double ms = 0.0;
    for (const auto& p : mLast.passes) {
        if (p.name.find(part) != std::string::npos) {
            ms += p.gpuMs;
        }
    }
    return ms;
}

} // namespace gt::app
