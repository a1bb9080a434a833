#pragma once
// The frame loop every front end runs: gaze source -> views -> Renderer::renderFrame -> output
// targets -> present or write. What differs between `render` (PNGs along a trace), `demo` (a
// window), `xr` (an OpenXR session), `eval` and `bench` (sequences read back and measured) are
// the stages, given as callables; the order, the frame count, the time along the sequence and
// the stopping rules (a stop request from SIGINT or SIGTERM among them) are written once, here.
#include <chrono>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "output_target.hpp"
#include "renderer.hpp"
#include "stop_request.hpp"
#include "view.hpp"

namespace gt::app {

// Time along a sequence: a fixed step per frame (reproducible: traces, camera paths, tests),
// or, with no step, the wall clock since the loop started.
class FrameClock {
public:
    using Clock = std::chrono::steady_clock;
    explicit FrameClock(double stepMs = 0.0, Clock::time_point start = Clock::now())
        : mStepMs(stepMs), mStart(start) {}
    // Milliseconds at frame `index`: index * step, or the wall time since the start.
    [[nodiscard]] double at(uint32_t index) const;
    [[nodiscard]] Clock::time_point start() const noexcept { return mStart; }

private:
    double mStepMs;
    Clock::time_point mStart;
};

struct FrameTick {
    uint32_t index = 0;  // frames rendered before this one
    double timeMs = 0.0; // FrameClock::at(index), sampled when the frame begins
};

// What a frame's first stage decided: render it, try again (nothing rendered: a minimised
// window, no swapchain image, an XR frame the runtime does not show), or end the loop.
enum class FrameStart { Render, Skip, Stop };

// What a stop request (stop_request.hpp) does to the loop. A fixed-length run (a sequence written
// or measured) fails before its next frame with Interrupted, so what it wrote is undone as after
// any failure. A live run (a window, an OpenXR session) is ended by its begin stage, which sees
// stopRequested() and ends the way its user would end it: the window closes after the current
// frame, the XR session is asked to exit and runs until the runtime ends it.
enum class OnStopRequest { Interrupt, BeginStageEnds };

template <typename Gaze> struct FrameStages {
    // Before anything else of a frame (input, the swapchain image, the XR frame). Optional.
    std::function<FrameStart(const FrameTick&)> begin;
    // The gaze source: where the viewer looks this frame.
    std::function<Gaze(const FrameTick&)> gaze;
    // The view builder: the frame's views (one, or both eyes) for that gaze.
    std::function<std::vector<render::View>(const FrameTick&, const Gaze&)> views;
    // The output target of each view, ready for this frame.
    std::function<std::vector<render::OutputTarget*>(const FrameTick&,
                                                     std::span<const render::View>)>
        targets;
    // Per-frame renderFrame options (a Graphviz dump of the first frame). Optional.
    std::function<render::FrameOptions(const FrameTick&)> options;
    // The per-frame callback once the frame is rendered: present it, write it, measure it.
    // Returns false to end the loop after this frame.
    std::function<bool(const FrameTick&, const Gaze&, std::span<const render::View>,
                       const render::FrameResult&)>
        done;
    // Live runs (a window, an OpenXR session) set BeginStageEnds and check in begin.
    OnStopRequest onStop = OnStopRequest::Interrupt;
    // The scene time, in seconds, animated scenes are posed at this frame (after begin, before
    // the views, which may follow an animated camera). Optional: without it the scene time is
    // sceneStartSeconds plus the tick's time, so a fixed step gives render's reproducible
    // frames and the wall clock the demo's real time.
    std::function<double(const FrameTick&)> sceneTime;
    double sceneStartSeconds = 0.0; // --time
};

// Runs frames until `frames` were rendered (0: until a stage stops the loop); returns how many
// were rendered. `renderer` is a render::Renderer (any type with its renderFrame, for tests).
// Throws Interrupted before a frame once a stop was requested, unless stages.onStop leaves that
// to the begin stage.
template <typename Gaze, typename FrameRenderer>
uint32_t runFrameLoop(FrameRenderer& renderer, const FrameClock& clock, uint32_t frames,
                      const FrameStages<Gaze>& stages) {
    FrameTick tick;
    while (frames == 0 || tick.index < frames) {
        if (stages.onStop == OnStopRequest::Interrupt) {
            throwIfStopRequested();
        }
        tick.timeMs = clock.at(tick.index);
        if (stages.begin) {
            const FrameStart start = stages.begin(tick);
            if (start == FrameStart::Stop) {
                break;
            }
            if (start == FrameStart::Skip) {
                continue;
            }
        }
        if constexpr (requires { renderer.setSceneTime(0.0); }) {
            renderer.setSceneTime(stages.sceneTime ? stages.sceneTime(tick)
                                                   : stages.sceneStartSeconds + tick.timeMs * 1e-3);
        }
        const Gaze gaze = stages.gaze(tick);
        const std::vector<render::View> views = stages.views(tick, gaze);
        const std::vector<render::OutputTarget*> targets = stages.targets(tick, views);
        const render::FrameResult result = renderer.renderFrame(
            views, targets, stages.options ? stages.options(tick) : render::FrameOptions{});
        const bool more = stages.done(tick, gaze, views, result);
        ++tick.index;
        if (!more) {
            break;
        }
    }
    return tick.index;
}

// One frame of one view into one target: the loop's single step, for the measurements that
// interleave methods frame by frame (eval, bench). Throws Interrupted first once a stop was
// requested: those are fixed-length runs.
render::FrameResult renderOneFrame(render::Renderer& renderer, const render::View& view,
                                   render::OutputTarget& target);

} // namespace gt::app
