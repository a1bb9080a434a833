#include "frame_loop.hpp"

namespace gt::app {

double FrameClock::at(uint32_t index) const {
    if (mStepMs > 0.0) return index * mStepMs;
    return std::chrono::duration<double, std::milli>(Clock::now() - mStart).count();
}

render::FrameResult renderOneFrame(render::Renderer& renderer, const render::View& view,
                                   render::OutputTarget& target) {
    throwIfStopRequested();
    render::OutputTarget* const t = &target;
    return renderer.renderFrame(std::span(&view, 1), std::span(&t, 1));
}

} // namespace gt::app
