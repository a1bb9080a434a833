#include "gaze/gaze_tracker.hpp"

#include <chrono>
#include <exception>

#include "error.hpp"
#include "pupil/starburst_detector.hpp"

namespace gt::eyetrack {

namespace {

std::unique_ptr<EyePipeline> checked(std::unique_ptr<EyePipeline> p) {
    if (!p || !p->mapper()) throw EyetrackError("gaze tracker: the pipeline needs a calibration");
    return p;
}

} // namespace

GazeTracker::GazeTracker(std::unique_ptr<EyePipeline> pipeline, GazeTrackerOptions options)
    : mPipeline(checked(std::move(pipeline))), mDisplay(mPipeline->mapper()->display()),
      mOptions(std::move(options)), mThread([this](const std::stop_token& st) { run(st); }) {}

GazeTracker::GazeTracker(std::unique_ptr<FrameSource> source, Calibration calibration,
                         GazeTrackerOptions options)
    : GazeTracker(std::make_unique<EyePipeline>(
                      std::move(source), std::make_unique<StarburstDetector>(),
                      std::make_unique<PolynomialMapper>(std::move(calibration)), options.filter),
                  options) {}

GazeTracker::~GazeTracker() {
    mThread.request_stop();
    if (mThread.joinable()) mThread.join();
}

std::optional<std::string> GazeTracker::error() const {
    const std::lock_guard lock(mErrorMutex);
    return mError;
}

bool GazeTracker::waitForFirstSample(double timeoutMs) const {
    const auto until = std::chrono::steady_clock::now() +
                       std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                           std::chrono::duration<double, std::milli>(timeoutMs));
    while (mMailbox.version() == 0 && !finished()) {
        if (std::chrono::steady_clock::now() >= until) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return mMailbox.version() > 0;
}

void GazeTracker::run(const std::stop_token& stop) {
    try {
        const bool pace = mOptions.paceRecordings && !mPipeline->source().liveClock();
        std::optional<double> firstMs;
        const auto start = std::chrono::steady_clock::now();
        while (!stop.stop_requested()) {
            auto frame = mPipeline->grab();
            if (!frame) break;
            if (pace) {
                if (!firstMs) firstMs = frame->tMs;
                const auto due =
                    start + std::chrono::duration_cast<std::chrono::nanoseconds>(
                                std::chrono::duration<double, std::milli>(frame->tMs - *firstMs));
                // Sleep in short steps so that a stop request is honoured promptly.
                while (!stop.stop_requested() && std::chrono::steady_clock::now() < due)
                    std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(
                        due - std::chrono::steady_clock::now(), std::chrono::milliseconds(5)));
            }
            const GazeSample s = *mPipeline->process(*frame).sample;
            if (s.saccade) ++mSaccades;
            mMailbox.publish(s);
            ++mFrames;
        }
    } catch (const std::exception& e) {
        const std::lock_guard lock(mErrorMutex);
        mError = e.what();
    }
    mFinished = true;
    mFinished.notify_all();
}

} // namespace gt::eyetrack
