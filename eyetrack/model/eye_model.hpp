#pragma once
// An eyeball fitted from a sequence of pupil ellipses (Świrski & Dodgson 2013, "A fully-automatic,
// temporally-coherent approach to unprojection"), and the optical axis it gives for each new
// ellipse. Corneal refraction is left out (the pupil is taken where it appears), as in the
// paper's first stage; a calibration rotation absorbs the constant part of its effect.
//  1. Each ellipse unprojects to two circles (model/ellipse_unprojection.hpp) of an assumed
//     pupil radius; both normals project to the same image line through the ellipse.
//  2. The eye's centre projects to the least-squares intersection of those lines (lines that
//     stray far from it are dropped and the intersection recomputed).
//  3. Of each ellipse's two circles, the one whose normal points away from that centre is the
//     pupil.
//  4. The eye's centre in 3D lies on the camera ray through its projection, at the depth that
//     brings it closest to all the pupils' normal lines; the eye's radius is the median distance
//     to the pupils.
//  5. A new ellipse's gaze: the camera ray through its (unprojected) centre meets the sphere; the
//     optical axis runs from the eye's centre through that point. Only the direction to the
//     pupil is used, so the assumed pupil radius, and pupil size changes, do not matter.
// The fit runs on a sliding window of recent confident ellipses, so when the headset slips the
// model moves with the eye: that is what makes it robust where a 2D polynomial is not.
#include <deque>
#include <optional>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "model/camera_intrinsics.hpp"
#include "model/ellipse_unprojection.hpp"

namespace gt::eyetrack {

struct EyeModelConfig {
    double pupilRadiusMm = 2.0; // assumed; sets the model's scale only
    int window = 600;           // ellipses kept for the fit (5 s at 120 Hz)
    int minObservations = 24;   // fewer: no fit
    double minSpreadDeg = 6.0;  // the normals must span this much, or the lines are parallel
    int refitEvery = 30;        // observations between refits
};

class EyeModel {
public:
    explicit EyeModel(CameraIntrinsics camera, EyeModelConfig config = {});

    // Adds an ellipse to the window (refits every refitEvery additions once ready).
    void add(const cv::RotatedRect& ellipse);
    // Refits from the window now; false (and the old model kept) when there is not enough
    // spread or too few ellipses.
    bool fit();
    [[nodiscard]] bool ready() const noexcept { return mReady; }
    // Unit optical axis (camera frame, from the eye's centre through the pupil) for an ellipse;
    // nullopt before the first fit or for a degenerate ellipse.
    [[nodiscard]] std::optional<cv::Vec3d> gaze(const cv::RotatedRect& ellipse) const;

    [[nodiscard]] const cv::Vec3d& centre() const noexcept { return mCentre; }
    [[nodiscard]] double radius() const noexcept { return mRadius; }
    [[nodiscard]] const CameraIntrinsics& camera() const noexcept { return mCamera; }
    [[nodiscard]] const EyeModelConfig& config() const noexcept { return mConfig; }
    void clearWindow() { mWindow.clear(); }

    // The fitted sphere, to start a tracking session from (the window is not saved).
    [[nodiscard]] nlohmann::json toJson() const;
    void setSphere(const cv::Vec3d& centre, double radius);

private:
    struct Observation {
        std::array<Circle3d, 2> circles;
        cv::Point2d centre2d;  // image of the pupil centre
        cv::Point2d direction; // unit image direction of the normals
    };
    [[nodiscard]] cv::Point2d project(const cv::Vec3d& p) const;

    CameraIntrinsics mCamera;
    EyeModelConfig mConfig;
    std::deque<Observation> mWindow;
    int mSinceFit = 0;
    bool mReady = false;
    cv::Vec3d mCentre{0, 0, 0};
    double mRadius = 0.0;
};

} // namespace gt::eyetrack
