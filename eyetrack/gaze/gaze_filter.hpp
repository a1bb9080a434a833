#pragma once
// From calibrated gaze points to the samples the renderer and other programs get.
//  - Confidence gate: samples below minConfidence are treated as lost.
//  - Blink state: while lost, the last good gaze is held (event Blink); the next good sample
//    restarts the filters rather than smoothing across the gap.
//  - I-VT (Salvucci & Goldberg 2000): angular velocity between consecutive samples above the
//    threshold (default 30 deg/s) is a saccade. Its first sample carries saccade = true, the
//    renderer's cue to drop temporal history.
//  - One Euro filter (Casiez, Roussel & Vogel 2012) in fixations and pursuit, with its cutoff
//    rising with speed; bypassed during saccades so the gaze jumps at once, and restarted where
//    the saccade lands.
#include <optional>

#include <opencv2/core/types.hpp>

#include "gaze/display_geometry.hpp"
#include "gaze/gaze_sample.hpp"

namespace gt::eyetrack {

// One Euro filter for one value.
class OneEuroFilter {
public:
    OneEuroFilter(double minCutoffHz, double beta, double derivativeCutoffHz)
        : mMinCutoff(minCutoffHz), mBeta(beta), mDCutoff(derivativeCutoffHz) {}
    double filter(double x, double dtSeconds);
    void reset() { mHave = false; }

private:
    double mMinCutoff, mBeta, mDCutoff;
    bool mHave = false;
    double mX = 0.0, mDx = 0.0;
};

struct GazeFilterConfig {
    DisplayGeometry display;
    // The gate on the starburst detector's reported confidence (the probability that the answer
    // is within 5 px, answer_confidence.hpp), chosen on development seeds alone: the lowest of
    // 0.6 / 0.65 / 0.7 / 0.75 / 0.8 at which each 50-seed set (gazetrace eyescore; a held-out
    // set is 50 seeds, and the sets' rates spread by 8 points) rejects 90 % of the wrong answers
    // and keeps 95 % of the right ones. Since 128 rays (starburst_detector.hpp) it is chosen on
    // the twelve sets of 600 further wild seeds (30001-30300, 40001-40300), first used in that
    // change, as the lowest at which the most sets meet both: at 0.75 eleven (30101-30150
    // rejects 89.8 %; the others at least 90.1 % and 95.2 %; all of them 92.75 % and 96.84 %),
    // at 0.7 nine, at 0.8 eleven. On wild 1-300 at 0.75 the worst set rejects 89.8 % (seeds
    // 201-250; 0.7: 88.8 %) and keeps 95.8 %, all of it 95.2 % and 97.0 %; hard 1-200 98.9 % and
    // 99.9 %. Kept at 0.75 for the first threshold that clears the noise and its refitted
    // confidence (answer_confidence.cpp): eleven of the twelve fresh sets meet both there
    // (30101-30150 rejects 89.2 %; all of them 93.09 % and 97.23 %), all twelve at 0.8 (the least
    // 90.3 % and 95.3 %), eleven at 0.7; counting the six sets of wild 1-300, seventeen of
    // eighteen at both 0.75 and 0.8 (at 0.8 wild 151-200 keeps 94.8 %). Hard 1-200 at 0.75:
    // 99.17 % and 99.85 %.
    // History: 0.7 with 64 rays, chosen on wild 1-300 (worst set 90.4 / 96.1 %; on the fresh
    // seeds two sets rejected under 90 % and one kept under 95 %); 0.7 until the confidence
    // took the pupil's shape into account (slivers under the lid had passed it as often as not),
    // then 0.58 and 0.6 on the detector's own product of factors; a gate chosen on 20 seeds,
    // 0.63, had rejected only 85 % on the first held-out set.
    double minConfidence = 0.75;
    double saccadeDegPerSecond = 30.0;
    double minCutoffHz = 1.0; // One Euro, in degrees
    double beta = 0.3;        // per deg/s: at 10 deg/s pursuit the cutoff is 4 Hz
    double derivativeCutoffHz = 1.0;
};

class GazeFilter {
public:
    explicit GazeFilter(GazeFilterConfig config);

    // gaze: calibrated screen point, or nullopt when no pupil was found.
    [[nodiscard]] GazeSample process(double tMs, std::optional<cv::Point2d> gaze,
                                     double confidence);

    [[nodiscard]] const GazeFilterConfig& config() const noexcept { return mConfig; }

private:
    GazeFilterConfig mConfig;
    OneEuroFilter mFx, mFy;
    bool mHaveLast = false; // a previous good raw sample (for velocity)
    cv::Point2d mLastRaw;
    double mLastTMs = 0.0;
    bool mInSaccade = false;
    bool mHaveOutput = false;
    GazeSample mLastOut;
};

} // namespace gt::eyetrack
