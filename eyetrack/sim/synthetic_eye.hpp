#pragma once
// Synthetic near-infrared eye images with exact ground truth, for testing and benchmarking the
// tracker (`gazetrace eyesim`, the `synthetic:SEED` frame source).
//
// Eye model: a sphere rotating about its centre, seen by an orthographic camera. The pupil and the
// iris are discs on a plane at distance R from the centre, perpendicular to the optical axis, so
// they project to exact ellipses: semi-axes (r, r cos(theta)) with the minor axis along the
// projected optical axis (theta = angle between the optical axis and the camera axis). The truth
// centre is the projected disc centre, which under orthographic projection is the ellipse centre.
// Around it: sclera, skin, eyelids (parabolas that follow the vertical gaze and close in blinks),
// eyelashes (some drooping over the eye in the hard preset), one to four corneal glints (the
// reflections of point lights on a 7.8 mm corneal sphere), defocus blur, exposure drift and sensor
// noise. Images are drawn at 2x and area-averaged, so edges are anti-aliased and truth is
// sub-pixel. Pixel centres are at integer coordinates, as in OpenCV.
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "sim/gaze_schedule.hpp"

namespace gt::eyetrack {

struct EyeSimConfig {
    cv::Size size{320, 240};
    double fps = 120.0;
    int frames = 600; // the gaze schedule is planned for this many frames
    std::uint64_t seed = 1;
    ScheduleConfig schedule; // its seed follows `seed`

    // Appearance; applyPreset() sets them, flags may override afterwards.
    int glints = 1;
    double blurSigma = 0.7;       // defocus, pixels
    double noiseSigma = 1.5;      // sensor noise, grey levels
    double exposureDrift = 0.0;   // relative gain amplitude
    double upperLidHeight = 82.0; // eye opening above the corner line at 240 px height
    double droopingLashes = 0.0;  // share of lashes hanging over the eye
};

// "clean": wide-open lids, one glint, little blur and noise, no blinks.
// "hard": low upper lid that covers part of the pupil, four glints, drooping lashes, strong blur,
// noise, exposure drift and blinks. Throws EyetrackError for an unknown name.
void applyPreset(EyeSimConfig& config, const std::string& preset);

struct EyeTruth {
    int frame = 0;
    double tMs = 0.0;
    cv::Point2d centre;      // pupil centre, image pixels
    double axisA = 0.0;      // semi-major axis, pixels
    double axisB = 0.0;      // semi-minor axis, pixels
    double angleDeg = 0.0;   // direction of the major axis, degrees from +x towards +y
    double visibility = 0.0; // share of the pupil's area not hidden by the lids
    double yawDeg = 0.0;     // eye rotation relative to the camera axis
    double pitchDeg = 0.0;
    GazeState gaze; // target, gaze point, phase, blink state
};

class SyntheticEye {
public:
    explicit SyntheticEye(EyeSimConfig config);

    // Frame index -> image (CV_8UC1) and its truth. Deterministic: same config, same pixels.
    [[nodiscard]] cv::Mat render(int frame, EyeTruth* truth = nullptr) const;
    [[nodiscard]] double frameTimeMs(int frame) const { return frame * 1000.0 / mConfig.fps; }
    [[nodiscard]] const EyeSimConfig& config() const noexcept { return mConfig; }
    [[nodiscard]] const GazeSchedule& schedule() const noexcept { return mSchedule; }

private:
    struct Lash {
        double u;      // base position along the lid, -1..1
        double length; // pixels at 240 px height
        double bend;   // curl
        bool droops;   // hangs down over the eye
    };

    EyeSimConfig mConfig;
    GazeSchedule mSchedule;
    double mScale = 1.0; // image height / 240
    cv::Point2d mEyeCentre;
    double mYaw0 = 0.0, mPitch0 = 0.0, mRollDeg = 0.0;
    double mPupilRadius = 20.0, mPupilPhase = 0.0;
    int mPupilLevel = 28, mIrisLevel = 110, mLashLevel = 40;
    std::vector<cv::Point2d> mGlintOffsets;
    std::vector<Lash> mLashes;
    cv::Mat mSkin, mSclera; // 2x textures
};

} // namespace gt::eyetrack
