#pragma once
// The eye tracker as a component for another program's frame loop (the renderer): a thread
// runs an EyePipeline (frame source -> PupilDetector -> GazeMapper -> GazeFilter, the same object
// `gazetrace track` drives) and publishes every sample to a GazeMailbox; the reader takes the
// newest sample when it starts a frame and never waits. Saccade onsets are also counted, so a
// reader that samples less often than the tracker (a renderer at 90 Hz, a tracker at 120+ Hz) still
// sees every saccade and can drop its temporal history (thesis, 3.1).
//
// Recordings are played at their own pace by default (a frame is processed at its timestamp
// relative to the first), so a video behaves like the camera it was recorded with.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "capture/frame_source.hpp"
#include "gaze/calibration.hpp"
#include "gaze/eye_pipeline.hpp"
#include "gaze/gaze_filter.hpp"
#include "gaze/gaze_mailbox.hpp"

namespace gt::eyetrack {

struct GazeTrackerOptions {
    bool paceRecordings = true; // false: process recordings as fast as possible
    GazeFilterConfig filter;    // its display is replaced by the calibration's
};

class GazeTracker {
public:
    // Starts the thread at once. The pipeline (which must have a mapper) is owned by the
    // tracker from here on.
    explicit GazeTracker(std::unique_ptr<EyePipeline> pipeline, GazeTrackerOptions options = {});
    // The default pipeline: the starburst detector and the 2D polynomial calibration.
    GazeTracker(std::unique_ptr<FrameSource> source, Calibration calibration,
                GazeTrackerOptions options = {});
    ~GazeTracker(); // stops and joins the thread
    GazeTracker(const GazeTracker&) = delete;
    GazeTracker& operator=(const GazeTracker&) = delete;

    [[nodiscard]] const GazeMailbox& mailbox() const noexcept { return mMailbox; }
    [[nodiscard]] const DisplayGeometry& display() const noexcept { return mDisplay; }
    [[nodiscard]] std::uint64_t saccades() const noexcept { return mSaccades.load(); }
    [[nodiscard]] std::uint64_t frames() const noexcept { return mFrames.load(); }
    // The source ran out (end of a recording) or failed; error() says why when it failed.
    [[nodiscard]] bool finished() const noexcept { return mFinished.load(); }
    [[nodiscard]] std::optional<std::string> error() const;
    // Waits until the first sample is published or the tracker finished, at most `timeoutMs`.
    bool waitForFirstSample(double timeoutMs) const;
    // Blocks until the source ran out or failed, however long that takes: a recording processed
    // as fast as possible ends when its last frame is done, on a slow build as on a fast one.
    void waitUntilFinished() const noexcept { mFinished.wait(false); }

private:
    void run(const std::stop_token& stop);

    std::unique_ptr<EyePipeline> mPipeline;
    DisplayGeometry mDisplay;
    GazeTrackerOptions mOptions;
    GazeMailbox mMailbox;
    std::atomic<std::uint64_t> mSaccades{0}, mFrames{0};
    std::atomic<bool> mFinished{false};
    mutable std::mutex mErrorMutex;
    std::optional<std::string> mError;
    std::jthread mThread; // last: starts after every member it uses exists
};

} // namespace gt::eyetrack
