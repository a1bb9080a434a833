// The front ends' frame loop (apps/support/frame_loop.hpp): the order of its stages, the frame
// index and time it hands them, and its rules for skipping and stopping (a stop request from
// SIGINT or SIGTERM among them), with a renderer that only records what it was given.
#include <csignal>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "frame_loop.hpp"
#include "stop_request.hpp"

namespace {

using gt::app::FrameClock;
using gt::app::FrameStages;
using gt::app::FrameStart;
using gt::app::FrameTick;
using gt::app::Interrupted;
using gt::app::OnStopRequest;
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
    int signalAfterFrame = -1; // a stop request once this frame is done (SIGTERM)

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
            if (static_cast<int>(t.index) == signalAfterFrame) {
                gt::app::testing::requestStop(SIGTERM);
            }
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

// Clears the stop request a test made, whatever the test's outcome.
struct StopRequestReset {
    ~StopRequestReset() { gt::app::testing::requestStop(0); }
};

TEST(FrameLoop, AStopRequestInterruptsAFixedLengthRunBeforeItsNextFrame) {
    const StopRequestReset reset;
    RecordingRenderer renderer;
    LoggedStages logged;
    logged.signalAfterFrame = 1;
    try {
        (void)gt::app::runFrameLoop(renderer, FrameClock(1.0), 10, logged.stages());
        ADD_FAILURE() << "the loop ran all its frames after SIGTERM";
    } catch (const Interrupted& e) {
        EXPECT_EQ(e.signal(), SIGTERM);
        EXPECT_EQ(e.exitStatus(), 143);
        EXPECT_STREQ(e.what(), "interrupted (SIGTERM)");
    }
    // The frame under way was finished; none began after it.
    EXPECT_EQ(renderer.views.size(), 2u);
    EXPECT_EQ(logged.log.back(), "done");
}

TEST(FrameLoop, ALiveRunsBeginStageEndsItAtAStopRequest) {
    const StopRequestReset reset;
    RecordingRenderer renderer;
    LoggedStages logged;
    logged.signalAfterFrame = 2;
    FrameStages<uint32_t> stages = logged.stages();
    stages.onStop = OnStopRequest::BeginStageEnds;
    const auto begin = stages.begin;
    stages.begin = [&](const FrameTick& t) {
        return gt::app::stopRequested() ? FrameStart::Stop : begin(t);
    };
    EXPECT_EQ(gt::app::runFrameLoop(renderer, FrameClock(1.0), 0, stages), 3u);
}

TEST(StopRequest, TheFirstSignalIsRecordedAndTheSecondGetsTheDefaultAction) {
    const StopRequestReset reset;
    gt::app::installStopHandlers();
    EXPECT_FALSE(gt::app::stopRequested());
    ASSERT_EQ(std::raise(SIGINT), 0); // would end the test binary without the handler
    EXPECT_EQ(gt::app::stopSignal(), SIGINT);
    EXPECT_THROW(gt::app::throwIfStopRequested(), Interrupted);
    for (const int signal : {SIGINT, SIGTERM}) {
        struct sigaction now {};
        ASSERT_EQ(sigaction(signal, nullptr, &now), 0);
        EXPECT_EQ(now.sa_handler, SIG_DFL) << signal;
    }
    // A live loop's check ends it; a fixed-length one's throws.
    EXPECT_TRUE(gt::app::liveRunEnds(true));
    EXPECT_THROW((void)gt::app::liveRunEnds(false), Interrupted);
}

TEST(StopRequest, ASignalIgnoredOnEntryStaysIgnored) {
    const StopRequestReset reset;
    struct sigaction ignore {
    }, now{};
    ignore.sa_handler = SIG_IGN;
    ASSERT_EQ(sigaction(SIGTERM, &ignore, nullptr), 0);
    gt::app::installStopHandlers();
    ASSERT_EQ(sigaction(SIGTERM, nullptr, &now), 0);
    EXPECT_EQ(now.sa_handler, SIG_IGN);
    ASSERT_EQ(std::raise(SIGTERM), 0);
    EXPECT_FALSE(gt::app::stopRequested());
    for (const int signal : {SIGINT, SIGTERM})
        std::signal(signal, SIG_DFL);
}

TEST(FrameLoop, WithoutAStepTheClockIsTheWallClock) {
    const auto start = FrameClock::Clock::now() - std::chrono::milliseconds(50);
    const FrameClock clock(0.0, start);
    EXPECT_GE(clock.at(7), 50.0); // not 7 * step
    EXPECT_EQ(FrameClock(2.5).at(4), 10.0);
}

} // namespace
