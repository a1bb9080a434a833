#pragma once
// The shape a pupil should have where it is seen: learnt from the eye's own whole pupils.
//
// A pupil is a circle on a sphere. Seen from a camera at a fixed place (the head-mounted case),
// its ellipse is that circle turned by the angle theta between the eye's optical axis and the
// camera's line of sight: in weak perspective the axis ratio is cos(theta), the minor axis lies
// along the line from the eyeball centre's image through the pupil's centre, and the distance
// between the two is R sin(theta), R the eyeball-centre-to-pupil distance in pixels (Świrski and
// Dodgson 2013, §3.1: the minor axes of the pupil ellipses meet at the projected eyeball centre;
// the 3D model in model/eye_model.hpp builds on the same geometry with a perspective camera).
// From ellipses seen whole the model fits that centre (least squares of the minor-axis lines,
// each weighted by sin^2 theta: a round pupil's minor axis says nothing about its direction) and
// R (least squares of the distances against sin theta), and predicts the ratio and the major
// axis's direction at any centre. Corneal refraction makes a real pupil look rounder than cos
// theta; fitting R to the observed ratios absorbs most of it, and the predictions are used as a
// band (refit_strategies.hpp, fitToEyeShape), not as exact values.
//
// The samples are a window of the most recent ones, so a headset that slips is relearnt.
#include <cstddef>
#include <optional>
#include <vector>

#include <opencv2/core/types.hpp>

namespace gt::eyetrack {

struct PupilShape {
    double axisRatio = 1.0;    // minor over major axis
    double majorAngleDeg = 0.; // direction of the major axis in the image, degrees (mod 180)
};

// An ellipse's shape (OpenCV's RotatedRect: full axes, angle of `width`, either axis first).
[[nodiscard]] PupilShape shapeOf(const cv::RotatedRect& ellipse);
// How far apart two major axes' directions are, degrees in [0, 90].
[[nodiscard]] double axisTurnDeg(double aDeg, double bDeg);

class PupilShapeModel {
public:
    // A whole pupil's ellipse (OpenCV's RotatedRect: full axes, angle of `width`).
    void add(const cv::RotatedRect& ellipse);
    // The expected shape of a pupil centred at `centre`; nullopt until the model is learnt (enough
    // samples, turned in enough directions, and fitting them: median ratio error under 0.05).
    [[nodiscard]] std::optional<PupilShape> predict(cv::Point2d centre) const;
    [[nodiscard]] bool ready() const noexcept { return mReady; }
    void reset();

    // Learnt parameters (for tests): the eyeball centre's image and R, pixels.
    [[nodiscard]] cv::Point2d eyeCentre() const noexcept { return mCentre; }
    [[nodiscard]] double eyeRadius() const noexcept { return mRadius; }

private:
    struct Sample {
        cv::Point2d centre;
        double ratio = 1.0;
        cv::Point2d major; // unit vector along the major axis
    };
    void refit();

    std::vector<Sample> mSamples; // ring buffer of the latest kWindow samples
    std::size_t mNext = 0;
    std::size_t mAdded = 0;
    bool mReady = false;
    cv::Point2d mCentre;
    double mRadius = 0.0;
};

} // namespace gt::eyetrack
