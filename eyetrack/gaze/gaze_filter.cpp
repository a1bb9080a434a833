#include "gaze/gaze_filter.hpp"

#include <cmath>
#include <numbers>

namespace gt::eyetrack {

namespace {

double smoothingFactor(double cutoffHz, double dt) {
    const double tau = 1.0 / (2.0 * std::numbers::pi * cutoffHz);
    return 1.0 / (1.0 + tau / dt);
}

} // namespace

double OneEuroFilter::filter(double x, double dt) {
    if (!mHave || dt <= 0.0) {
        mHave = true;
        mX = x;
        mDx = 0.0;
        return x;
    }
    const double dx = (x - mX) / dt;
    mDx += smoothingFactor(mDCutoff, dt) * (dx - mDx);
    const double cutoff = mMinCutoff + mBeta * std::abs(mDx);
    mX += smoothingFactor(cutoff, dt) * (x - mX);
    return mX;
}

GazeFilter::GazeFilter(GazeFilterConfig config)
    : mConfig(config), mFx(config.minCutoffHz, config.beta, config.derivativeCutoffHz),
      mFy(config.minCutoffHz, config.beta, config.derivativeCutoffHz) {}

GazeSample GazeFilter::process(double tMs, std::optional<cv::Point2d> gaze, double confidence) {
    GazeSample out;
    out.tMs = tMs;
    out.confidence = static_cast<float>(confidence);
    if (!gaze || confidence < mConfig.minConfidence || !std::isfinite(gaze->x) ||
        !std::isfinite(gaze->y)) {
        // Lost (blink, look-away): hold the last good gaze, forget the motion state.
        out.event = GazeEvent::Blink;
        if (mHaveOutput) {
            out.x = mLastOut.x;
            out.y = mLastOut.y;
        } else {
            out.x = static_cast<float>(0.5 * mConfig.display.widthPx);
            out.y = static_cast<float>(0.5 * mConfig.display.heightPx);
        }
        mHaveLast = false;
        mInSaccade = false;
        mFx.reset();
        mFy.reset();
        return out;
    }

    const double ppd = mConfig.display.pixelsPerDegreeAtCentre();
    double velocity = 0.0;
    const double dt = mHaveLast ? (tMs - mLastTMs) / 1000.0 : 0.0;
    if (mHaveLast && dt > 0.0) velocity = mConfig.display.angularDistanceDeg(mLastRaw, *gaze) / dt;
    const bool saccade = velocity > mConfig.saccadeDegPerSecond;

    cv::Point2d g = *gaze;
    if (saccade) {
        out.event = GazeEvent::Saccade;
        out.saccade = !mInSaccade; // onset
        mInSaccade = true;
        mFx.reset(); // bypass, and restart from wherever the saccade lands
        mFy.reset();
    } else {
        mInSaccade = false;
        out.event = GazeEvent::Fixation;
        g.x = mFx.filter(gaze->x / ppd, dt) *
              ppd; // filtered in degrees: parameters are display-independent
        g.y = mFy.filter(gaze->y / ppd, dt) * ppd;
    }
    out.x = static_cast<float>(g.x);
    out.y = static_cast<float>(g.y);
    mHaveLast = true;
    mLastRaw = *gaze;
    mLastTMs = tMs;
    mHaveOutput = true;
    mLastOut = out;
    return out;
}

} // namespace gt::eyetrack
