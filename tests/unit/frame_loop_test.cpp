// The front ends' frame loop (apps/support/frame_loop.hpp): the order of its stages, the frame
// index and time it hands them, and its rules for skipping and stopping, with a renderer that
// only records what it was given.
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "frame_loop.hpp"

namespace {

using gt::app::FrameClock;
using gt::app::FrameStages;
using gt::app::FrameStart;
using gt::app::FrameTick;
using gt::render::FrameResult;
using gt::render::OutputTarget;
using gt::render::View;

struct RecordingRenderer {
    std::vector<std::size_t> views;
    std::vector<bool> graphviz;
    FrameResult renderFrame(std::span<const View> v, std::span<OutputTarget* const> targets,
                            const gt::render::FrameOptions& options) {
        EXPECT_EQ(v.size(), targets.size());
        views.push_back(v.size());
        graphviz.push_back(options.graphviz);
        FrameResult r;
        r.number = views.size();
        return r;
    }
};

// Stages that log their calls; `begin` answers from `starts` (Render once they run out).
struct LoggedStages {
    std::vector<FrameStart> starts;
    std::vector<std::string> log;
    std::vector<double> times;
    bool stopAfterDone = false;

    FrameStages<uint32_t> stages() {
        FrameStages<uint32_t> s;
        s.begin = [this](const FrameTick& t) {
            log.push_back("begin " + std::to_string(t.index));
            if (starts.empty()) return FrameStart::Render;
            const FrameStart f = starts.front();
            starts.erase(starts.begin());
            return f;
        };
        s.gaze = [this](const FrameTick& t) {
            log.push_back("gaze");
            return t.index;
        };
        s.views = [this](const FrameTick& t, const uint32_t& gaze) {
            EXPECT_EQ(gaze, t.index); // the views see this frame's gaze
            log.push_back("views");
            return std::vector<View>(2);
        };
        s.targets = [this](const FrameTick&, std::span<const View> v) {
            log.push_back("targets");
            return std::vector<OutputTarget*>(v.size(), nullptr);
        };
        s.options = [](const FrameTick& t) {
            return gt::render::FrameOptions{.graphviz = t.index == 0};
        };
        s.done = [this](const FrameTick& t, const uint32_t&, std::span<const View> v,
                        const FrameResult& r) {
            EXPECT_EQ(v.size(), 2u);
            EXPECT_EQ(r.number, t.index + 1); // the result of this frame's renderFrame
            times.push_back(t.timeMs);
            log.push_back("done");
            return !stopAfterDone;
        };
        return s;
    }
};

TEST(FrameLoop, StagesRunInOrderAndSkippedFramesKeepTheirIndex) {
    RecordingRenderer renderer;
    LoggedStages logged;
    logged.starts = {FrameStart::Render, FrameStart::Skip, FrameStart::Skip};
    EXPECT_EQ(gt::app::runFrameLoop(renderer, FrameClock(10.0), 3, logged.stages()), 3u);
    const std::vector<std::string> expected = {
        "begin 0", "gaze",    "views", "targets", "done", "begin 1", "begin 1", "begin 1", "gaze",
        "views",   "targets", "done",  "begin 2", "gaze", "views",   "targets", "done"};
    EXPECT_EQ(logged.log, expected);
    // Time along the sequence: the fixed step times the frame index, skips or not.
    EXPECT_EQ(logged.times, (std::vector<double>{0.0, 10.0, 20.0}));
    EXPECT_EQ(renderer.views, (std::vector<std::size_t>{2, 2, 2}));
    EXPECT_EQ(renderer.graphviz, (std::vector<bool>{true, false, false}));
}

TEST(FrameLoop, StopsWhenBeginOrDoneSaysSo) {
    {
        RecordingRenderer renderer;
        LoggedStages logged;
        logged.starts = {FrameStart::Render, FrameStart::Render, FrameStart::Stop};
        // No frame count: only the stage ends the loop, and nothing of the stopped frame runs.
        EXPECT_EQ(gt::app::runFrameLoop(renderer, FrameClock(1.0), 0, logged.stages()), 2u);
        EXPECT_EQ(logged.log.back(), "begin 2");
        EXPECT_EQ(renderer.views.size(), 2u);
    }
    {
        RecordingRenderer renderer;
        LoggedStages logged;
        logged.stopAfterDone = true;
        EXPECT_EQ(gt::app::runFrameLoop(renderer, FrameClock(1.0), 5, logged.stages()), 1u);
        EXPECT_EQ(renderer.views.size(), 1u);
    }
}

TEST(FrameLoop, WithoutAStepTheClockIsTheWallClock) {
    const auto start = FrameClock::Clock::now() - std::chrono::milliseconds(50);
    const FrameClock clock(0.0, start);
    EXPECT_GE(clock.at(7), 50.0); // not 7 * step
    EXPECT_EQ(FrameClock(2.5).at(4), 10.0);
}

} // namespace
