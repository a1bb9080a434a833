#pragma once
// Two eyes into one gaze: pairing the eyes' samples, a combined gaze point, and vergence.
//
// Pairing. Two cameras are rarely synchronised (and one camera that sees both eyes gives both at
// once, which is the easy case). Each eye's samples are kept in time order; a sample is paired
// with the other eye's newest sample when their time stamps differ by at most `maxSkewMs`
// (default 1.5 frame periods at 120 Hz: a free-running pair is never more than one period
// apart, so every sample finds a partner while both eyes stream). Without a partner (the other
// eye blinking, lost or stalled), the sample goes out alone as the combined gaze. A skew of up to
// one period means that during a saccade the two eyes are compared at slightly different
// moments; vergence is therefore only reported when both eyes are in a fixation.
//
// Geometry (display frame, cm: x right, y down, z towards the screen; the eyes at x = -+ ipd/2
// on the line z = 0, the screen at z = distance). Each eye's calibration maps it onto the screen
// plane, where its line of sight meets it: X_left, X_right. The lines meet at depth
//   z = D * ipd / (ipd + X_left - X_right)
// (crossed lines, X_left > X_right, meet in front of the screen), which is the fixation distance;
// the vergence is the angle between the two lines. The combined gaze is the mean of the two
// screen points, which is where the line from between the eyes through the fixation point meets
// the screen.
#include <optional>

#include <opencv2/core/types.hpp>

#include "gaze/display_geometry.hpp"
#include "gaze/gaze_sample.hpp"

namespace gt::eyetrack {

enum class Eye { Left = 0, Right = 1 };

struct Vergence {
    double angleDeg = 0.0;   // between the two lines of sight
    double distanceCm = 0.0; // fixation depth from the eyes' baseline; +inf when parallel
};

// nullopt when the lines diverge (a calibration error or a wrong eye order).
[[nodiscard]] std::optional<Vergence> vergenceOf(const DisplayGeometry& d, double ipdMm,
                                                 cv::Point2d leftOnScreen,
                                                 cv::Point2d rightOnScreen);
// An eye's own gaze angles (yaw right, pitch up) towards a screen point.
[[nodiscard]] cv::Point2d eyeAnglesDeg(const DisplayGeometry& d, double ipdMm, Eye eye,
                                       cv::Point2d onScreen);

struct BinocularSample {
    GazeSample combined;
    std::optional<GazeSample> left, right;
    std::optional<Vergence> vergence; // both eyes valid and fixating
};

class BinocularCombiner {
public:
    BinocularCombiner(DisplayGeometry display, double ipdMm = 63.0, double maxSkewMs = 12.5);

    // One eye's filtered sample (per eye in time order); returns the combined sample.
    [[nodiscard]] BinocularSample push(Eye eye, const GazeSample& sample);
    [[nodiscard]] double ipdMm() const noexcept { return mIpdMm; }

private:
    DisplayGeometry mDisplay;
    double mIpdMm, mMaxSkewMs;
    std::optional<GazeSample> mLatest[2];
};

} // namespace gt::eyetrack
