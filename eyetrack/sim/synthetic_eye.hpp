#pragma once
// Synthetic near-infrared eye images with exact ground truth, for testing and benchmarking the
// tracker (`gazetrace eyesim`, the `synthetic:SEED` frame source).
//
// Eye model, in millimetres in the camera's frame (x right, y down, z forward): a sphere rotating
// about its centre E, 35 mm in front of the camera. The pupil and the iris are discs on the plane
// 11 mm from E, perpendicular to the optical axis g; the cornea is a 7.8 mm sphere whose centre
// is 5.5 mm along g. The eye points at the target on the display: g is the direction from the
// eye to the target in the display's frame, turned into the camera's frame by the camera's pose
// (below the eye, tilted up by `pitch0`, sideways by `yaw0`, rolled). The camera is either
//  - orthographic (the default for the clean and hard presets): a fixed 9.1 px/mm at the eye
//    (on a 240-row image), so discs project to exact ellipses centred on the disc centre; or
//  - perspective (`perspective`, always in the wild preset): a pinhole with `intrinsics`, so the
//    pupil outline is the exact projection of a 3D circle (an ellipse whose centre is not quite
//    the projected disc centre: the truth centre is the ellipse's, what a 2D detector sees; the
//    3D truth is written beside it). This is what the 3D eye model (model/eye_model.hpp) fits.
// Headset slippage (`slipMm`, `slipDeg`, from `slipAtMs` on) moves the headset — camera and
// display together — against the head: the eye centre moves by slipMm in the camera's frame and
// the face (lids, skin) turns by slipDeg about the camera axis; the eye still looks at the same
// display targets, so a tracker must follow the moved eye without recalibrating.
// Around the eye: sclera, skin, eyelids (parabolas that follow the vertical gaze and close in
// blinks), eyelashes, one to four corneal glints (point lights around the camera reflected on the
// cornea), defocus blur, exposure drift and sensor noise. The wider variation a detector must not
// be tuned away from (thick mascara lashes over the pupil, shadows and make-up darker than the
// pupil, low pupil/iris contrast, glints on the pupil border, steep camera angles, a raised lower
// lid, small and large pupils) is drawn per seed by the "wild" preset. Images are drawn at 2x and
// area-averaged, so edges are anti-aliased and truth is sub-pixel. Pixel centres are at integer
// coordinates, as in OpenCV.
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "model/camera_intrinsics.hpp"
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
    // The wider variation (0 / false: off).
    double mascara = 0.0;       // share of lashes drawn thick and darker than the pupil
    int shadows = 0;            // blurred patches outside the eye, darker than the pupil
    bool eyeliner = false;      // a band darker than the pupil along the upper lid's margin
    double irisContrast = 0.0;  // iris minus pupil grey level; 0: drawn from 60..100
    int borderGlints = 0;       // glints sitting on the pupil's outline
    double cameraTiltDeg = 0.0; // added to the camera's upward tilt (steep views)
    double lowerLidRaise = 0.0; // lower lid raised by this (px at 240 rows)
    double pupilMinPx = 15.0;   // pupil radius range at 240 rows (drawn per seed)
    double pupilMaxPx = 24.0;
    double pupilDilation = 0.08; // relative amplitude of the slow size change

    // Camera.
    bool perspective = false;
    CameraIntrinsics intrinsics; // perspective; unset (fx 0): CameraIntrinsics::eyesimDefault
    cv::Vec3d slipMm{0.0, 0.0, 0.0};
    double slipDeg = 0.0;
    double slipAtMs = -1.0; // < 0: no slippage

    // Binocular clips: the two eyes share seed and schedule and differ in eyeOffsetMm (the eye's
    // x in the display's frame: -IPD/2 left, +IPD/2 right) and appearanceSeed (0: seed).
    double eyeOffsetMm = 0.0;
    std::uint64_t appearanceSeed = 0;
    // In free viewing the eyes converge at this distance (cm) along the line of sight from
    // between the eyes through the gaze point, as on 3D content; 0: on the screen. Calibration
    // and validation targets are always on the screen.
    double fixationDepthCm = 0.0;
};

// The looks applyPreset() gives a synthetic eye.
enum class EyeSimPreset {
    Clean, // wide-open lids, one glint, little blur and noise, no blinks
    Hard,  // low upper lid that covers part of the pupil, four glints, drooping lashes, strong
           // blur, noise, exposure drift and blinks
    Wild,  // a perspective camera and, drawn from config.seed (set it first), each of the wider
           // variations on or off and of random strength, over random lids, glints, blur, noise
};
void applyPreset(EyeSimConfig& config, EyeSimPreset preset);

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
    // 3D truth in the camera's frame (mm): eyeball centre, optical axis (unit, from the eye
    // centre through the pupil), pupil radius.
    cv::Vec3d eyeCentreMm;
    cv::Vec3d gazeDirection;
    double pupilRadiusMm = 0.0;
    cv::Vec3d fixationMm; // the fixated point, display frame (origin between the eyes)
};

class SyntheticEye {
public:
    explicit SyntheticEye(EyeSimConfig config);

    // Frame index -> image (CV_8UC1) and its truth. Deterministic: same config, same pixels.
    [[nodiscard]] cv::Mat render(int frame, EyeTruth* truth = nullptr) const;
    [[nodiscard]] double frameTimeMs(int frame) const { return frame * 1000.0 / mConfig.fps; }
    [[nodiscard]] const EyeSimConfig& config() const noexcept { return mConfig; }
    [[nodiscard]] const GazeSchedule& schedule() const noexcept { return mSchedule; }
    // The camera as the 3D eye model should assume it (the orthographic camera's focal length is
    // its scale times the eye's distance).
    [[nodiscard]] const CameraIntrinsics& intrinsics() const noexcept { return mIntrinsics; }

private:
    struct Lash {
        double u;      // base position along the lid, -1..1
        double length; // pixels at 240 px height
        double bend;   // curl
        bool droops;   // hangs down over the eye
        bool mascara;  // thick and very dark
    };
    [[nodiscard]] cv::Point2d project(const cv::Vec3d& p) const;

    EyeSimConfig mConfig;
    GazeSchedule mSchedule;
    double mScale = 1.0; // image height / 240
    CameraIntrinsics mIntrinsics;
    cv::Point2d mEyeCentre; // image position of the eye centre before slippage
    cv::Vec3d mEyeMm;       // the eye centre in the camera's frame before slippage
    double mYaw0 = 0.0, mPitch0 = 0.0, mRollDeg = 0.0;
    double mPupilRadius = 20.0, mPupilPhase = 0.0;
    int mPupilLevel = 28, mIrisLevel = 110, mLashLevel = 40;
    std::vector<cv::Vec3d> mLights;         // glint light positions, camera frame (mm)
    std::vector<double> mBorderGlintAngles; // where border glints sit on the pupil outline
    std::vector<Lash> mLashes;
    cv::Mat mSkin, mSclera; // 2x textures
};

} // namespace gt::eyetrack
