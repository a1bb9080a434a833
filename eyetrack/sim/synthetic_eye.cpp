#include "sim/synthetic_eye.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include <opencv2/imgproc.hpp>

#include "error.hpp"

namespace gt::eyetrack {

namespace {

constexpr int kSuper = 2; // drawn at 2x, area-averaged down
constexpr int kShift = 8; // sub-pixel bits for OpenCV's drawing functions
constexpr double kDeg = std::numbers::pi / 180.0;

// Pixel i of the 2x canvas covers [i-0.5, i+0.5]; pixel u of the image is the mean of canvas
// pixels 2u and 2u+1, centred at 2u+0.5. So image x maps to canvas 2x+0.5 = 2(x+0.25), stored in
// OpenCV's fixed point for sub-pixel drawing.
cv::Point fixed(cv::Point2d p) {
    const double s = kSuper * static_cast<double>(1 << kShift);
    return {static_cast<int>(std::lround((p.x + 0.25) * s)),
            static_cast<int>(std::lround((p.y + 0.25) * s))};
}
int fixedLength(double v) {
    return static_cast<int>(std::lround(v * kSuper * static_cast<double>(1 << kShift)));
}

cv::Point2d rotate(cv::Point2d v, double deg) {
    const double c = std::cos(deg * kDeg), s = std::sin(deg * kDeg);
    return {c * v.x - s * v.y, s * v.x + c * v.y};
}

// A smooth random field: a coarse grid of random values upsampled with cubic interpolation.
cv::Mat lowFrequencyNoise(cv::Size size, int cells, double amplitude, std::mt19937_64& rng) {
    std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
    cv::Mat coarse(cells * 3 / 4 + 2, cells + 2, CV_32F);
    for (int y = 0; y < coarse.rows; ++y)
        for (int x = 0; x < coarse.cols; ++x)
            coarse.at<float>(y, x) = uni(rng) * static_cast<float>(amplitude);
    cv::Mat field;
    cv::resize(coarse, field, size, 0, 0, cv::INTER_CUBIC);
    return field;
}

constexpr double kPxPerMm = 9.1;        // at the eye, on a 240-row image
constexpr double kEyeDistanceMm = 35.0; // camera to eye centre
constexpr double kPupilPlaneMm = 11.0;  // eye centre to the pupil (and iris) plane
constexpr double kIrisRadiusMm = 5.05;
constexpr double kCorneaOffsetMm = 5.5; // eye centre to the corneal sphere's centre
constexpr double kCorneaRadiusMm = 7.8;

cv::Vec3d rotateX(const cv::Vec3d& v, double deg) {
    const double c = std::cos(deg * kDeg), s = std::sin(deg * kDeg);
    return {v[0], c * v[1] - s * v[2], s * v[1] + c * v[2]};
}
cv::Vec3d rotateY(const cv::Vec3d& v, double deg) {
    const double c = std::cos(deg * kDeg), s = std::sin(deg * kDeg);
    return {c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2]};
}
cv::Vec3d rotateZ(const cv::Vec3d& v, double deg) {
    const cv::Point2d r = rotate({v[0], v[1]}, deg);
    return {r.x, r.y, v[2]};
}

// Two unit vectors spanning the plane perpendicular to n.
std::pair<cv::Vec3d, cv::Vec3d> planeBasis(const cv::Vec3d& n) {
    const cv::Vec3d helper = std::abs(n[1]) < 0.9 ? cv::Vec3d(0, 1, 0) : cv::Vec3d(1, 0, 0);
    const cv::Vec3d u = cv::normalize(helper.cross(n));
    return {u, n.cross(u)};
}

} // namespace

void applyPreset(EyeSimConfig& c, EyeSimPreset preset) {
    if (preset == EyeSimPreset::Clean) {
        c.glints = 1;
        c.blurSigma = 0.7;
        c.noiseSigma = 1.5;
        c.exposureDrift = 0.0;
        c.upperLidHeight = 82.0;
        c.droopingLashes = 0.0;
        c.schedule.blinks = false;
    } else if (preset == EyeSimPreset::Hard) {
        c.glints = 4;
        c.blurSigma = 1.6;
        c.noiseSigma = 6.0;
        c.exposureDrift = 0.15;
        c.upperLidHeight = 36.0;
        c.droopingLashes = 0.3;
        c.schedule.blinks = true;
    } else {
        // Each variation on for a share of the seeds, at a random strength, so a set of seeds
        // covers them alone and together.
        std::mt19937_64 rng(c.seed * 0x9E3779B97F4A7C15ull + 17);
        std::uniform_real_distribution<double> uni(0.0, 1.0);
        auto range = [&](double a, double b) { return a + (b - a) * uni(rng); };
        auto chance = [&](double p) { return uni(rng) < p; };
        c.perspective = true;
        c.glints = static_cast<int>(range(1, 4.99));
        c.blurSigma = range(0.6, 2.0);
        c.noiseSigma = range(1.5, 7.0);
        c.exposureDrift = range(0.0, 0.2);
        c.upperLidHeight = range(34, 80);
        c.droopingLashes = range(0.0, 0.35);
        c.schedule.blinks = true;
        c.mascara = chance(0.5) ? range(0.3, 0.8) : 0.0;
        c.shadows = chance(0.5) ? static_cast<int>(range(1, 3.99)) : 0;
        c.eyeliner = chance(0.4);
        c.irisContrast = chance(0.35) ? range(18, 34) : 0.0;
        c.borderGlints = chance(0.5) ? static_cast<int>(range(1, 2.99)) : 0;
        c.cameraTiltDeg = chance(0.35) ? range(15, 28) : 0.0;
        c.lowerLidRaise = chance(0.35) ? range(10, 26) : 0.0;
        c.pupilMinPx = 8.0;
        c.pupilMaxPx = 30.0;
        c.pupilDilation = range(0.05, 0.25);
    }
}

SyntheticEye::SyntheticEye(EyeSimConfig config)
    : mConfig([&] {
          config.schedule.seed = config.seed;
          return config;
      }()),
      mSchedule(mConfig.schedule, mConfig.frames * 1000.0 / mConfig.fps + 1.0) {
    if (mConfig.size.width < 32 || mConfig.size.height < 24)
        throw EyetrackError("eyesim: image size must be at least 32x24");
    if (mConfig.pupilMinPx <= 0.0 || mConfig.pupilMaxPx < mConfig.pupilMinPx)
        throw EyetrackError("eyesim: pupil radius range must be positive and ordered");
    const std::uint64_t look = mConfig.appearanceSeed != 0 ? mConfig.appearanceSeed : mConfig.seed;
    std::mt19937_64 rng(look * 0xD1B54A32D192ED03ull + 5);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    auto range = [&](double a, double b) { return a + (b - a) * uni(rng); };

    mScale = mConfig.size.height / 240.0;
    const double s = mScale;
    mIntrinsics = mConfig.perspective && mConfig.intrinsics.valid()
                      ? mConfig.intrinsics
                      : CameraIntrinsics::eyesimDefault(mConfig.size);
    mEyeCentre = {0.5 * mConfig.size.width + range(-15, 15) * s,
                  0.5 * mConfig.size.height + range(-8, 8) * s};
    const cv::Vec3d ray = mIntrinsics.unproject(mEyeCentre);
    mEyeMm = ray * kEyeDistanceMm;
    // The camera sits below and to one side of the screen: looking at the screen centre the eye
    // is rotated up and sideways relative to the camera axis, and the image is rolled.
    mYaw0 = range(-6, 6);
    mPitch0 = range(2, 10) + mConfig.cameraTiltDeg;
    mRollDeg = range(-8, 8);
    mPupilRadius = range(mConfig.pupilMinPx, mConfig.pupilMaxPx) * s;
    mPupilPhase = range(0, 2 * std::numbers::pi);
    mPupilLevel = static_cast<int>(range(18, 36));
    mIrisLevel = mConfig.irisContrast > 0.0 ? mPupilLevel + static_cast<int>(mConfig.irisContrast)
                                            : static_cast<int>(range(95, 125));
    mLashLevel = static_cast<int>(range(30, 50));
    // Glint lights on a ring around the camera, 12-20 degrees off its axis as seen from the eye.
    for (int i = 0; i < mConfig.glints; ++i) {
        const double a = (i * 90.0 + 45.0 + range(-10, 10)) * kDeg, tilt = range(12, 20) * kDeg;
        const double r = kEyeDistanceMm * std::tan(tilt);
        mLights.emplace_back(r * std::cos(a), r * std::sin(a), 0.0);
    }
    for (int i = 0; i < mConfig.borderGlints; ++i)
        mBorderGlintAngles.push_back(range(0, 2 * std::numbers::pi));
    const int lashes = static_cast<int>(range(35, 60));
    for (int i = 0; i < lashes; ++i) {
        const bool mascara = uni(rng) < mConfig.mascara;
        // Mascara-thick lashes hang over the eye more often, and far enough to cross the pupil.
        const bool droops =
            uni(rng) < (mascara ? std::max(0.35, mConfig.droopingLashes) : mConfig.droopingLashes);
        // One draw per statement, in GCC's order (gaze_schedule.cpp says why).
        const double base = range(9, 18);
        const double thick = mascara ? range(1.2, 1.9) : 1.0;
        const double length = base * (droops ? 1.3 : 1.0) * thick;
        mLashes.push_back({range(-0.85, 0.85), length, range(-0.6, 0.6), droops, mascara});
    }
    const cv::Size big(mConfig.size.width * kSuper, mConfig.size.height * kSuper);
    const double skinLevel = range(145, 180), scleraLevel = range(175, 200);
    mSkin = lowFrequencyNoise(big, 8, 18.0, rng) + skinLevel;
    mSclera = lowFrequencyNoise(big, 10, 8.0, rng) + scleraLevel;
    // The sclera darkens towards the eye corners (it curves away from the lights).
    for (int y = 0; y < big.height; ++y) {
        for (int x = 0; x < big.width; ++x) {
            const double u = (x / double(kSuper) - mEyeCentre.x) / (125.0 * s);
            mSclera.at<float>(y, x) -= static_cast<float>(45.0 * u * u);
        }
    }
    // Shadows (a nose, a frame, a cheek in half-light) outside the eye, darker than the pupil:
    // blurred blobs towards the image's corners and sides.
    for (int i = 0; i < mConfig.shadows; ++i) {
        cv::Mat blob = cv::Mat::zeros(big, CV_32F);
        const double rx = range(14, 34) * s, ry = rx * range(0.5, 1.0);
        const double side = uni(rng) < 0.5 ? -1.0 : 1.0;
        const double dy = range(-110, 110); // one draw per statement, in GCC's order
        const double dx = range(120, 170);
        const cv::Point2d at(mEyeCentre.x + side * dx * s, mEyeCentre.y + dy * s);
        cv::ellipse(blob, fixed(at), {fixedLength(rx), fixedLength(ry)}, range(0, 180), 0, 360,
                    cv::Scalar(1.0), cv::FILLED, cv::LINE_AA, kShift);
        cv::GaussianBlur(blob, blob, cv::Size(), 0.35 * rx * kSuper);
        const double level = std::max(2.0, mPupilLevel - range(6, 16));
        mSkin = mSkin.mul(1.0 - blob) + blob * level;
    }
    mSkin.convertTo(mSkin, CV_8U);
    mSclera.convertTo(mSclera, CV_8U);
}

cv::Point2d SyntheticEye::project(const cv::Vec3d& p) const {
    if (mConfig.perspective) return mIntrinsics.project(p);
    const double k = mIntrinsics.fx / kEyeDistanceMm; // px per mm at the eye
    return {mIntrinsics.cx + k * p[0], mIntrinsics.cy + k * p[1]};
}

cv::Mat SyntheticEye::render(int frame, EyeTruth* truth) const {
    const double s = mScale;
    const double tMs = frameTimeMs(frame);
    const GazeState g = mSchedule.at(tMs);
    const bool slipped = mConfig.slipAtMs >= 0.0 && tMs >= mConfig.slipAtMs;
    const cv::Vec3d slip = slipped ? mConfig.slipMm : cv::Vec3d(0, 0, 0);
    const double faceRoll = slipped ? mConfig.slipDeg : 0.0;

    // The eye points at the target: its direction from the eye in the display's frame (x right,
    // y down, z towards the screen), then into the camera's frame — the camera faces the eye (a
    // half turn about y), tilted up by pitch0, turned by yaw0 and rolled. The eye's offset in
    // the display's frame after slippage changes the direction slightly (parallax).
    const DisplayGeometry& d = mConfig.schedule.display;
    const double mmPerPx = 10.0 * d.cmPerPixel();
    auto displayToCamera = [&](const cv::Vec3d& v) {
        return rotateZ(rotateX(rotateY(cv::Vec3d(-v[0], v[1], -v[2]), mYaw0), -mPitch0), mRollDeg);
    };
    auto cameraToDisplay = [&](const cv::Vec3d& v) {
        const cv::Vec3d u = rotateY(rotateX(rotateZ(v, -mRollDeg), mPitch0), -mYaw0);
        return cv::Vec3d(-u[0], u[1], -u[2]);
    };
    const cv::Vec3d slipDisplay = cameraToDisplay(slip);
    const cv::Vec3d onScreen((g.gaze.x - 0.5 * d.widthPx) * mmPerPx,
                             (g.gaze.y - 0.5 * d.heightPx) * mmPerPx, 10.0 * d.distanceCm);
    const cv::Vec3d fixation = g.phase == GazePhase::Free && mConfig.fixationDepthCm > 0.0
                                   ? onScreen * (mConfig.fixationDepthCm / d.distanceCm)
                                   : onScreen;
    const cv::Vec3d eyeInDisplay = cv::Vec3d(mConfig.eyeOffsetMm, 0.0, 0.0) + slipDisplay;
    const cv::Vec3d gaze = cv::normalize(displayToCamera(cv::normalize(fixation - eyeInDisplay)));
    const cv::Vec3d eyeMm = mEyeMm + slip;
    const cv::Point2d ang = d.anglesDeg(g.gaze);

    // Pupil, iris and cornea in 3D, then projected.
    const double rpPx =
        mPupilRadius *
        (1.0 + mConfig.pupilDilation * std::sin(2 * std::numbers::pi * tMs / 4000.0 + mPupilPhase));
    const double rp = rpPx / (kPxPerMm * s);
    const cv::Vec3d pupilCentre = eyeMm + gaze * kPupilPlaneMm;
    const std::pair<cv::Vec3d, cv::Vec3d> basis = planeBasis(gaze);
    const cv::Vec3d bu = basis.first, bv = basis.second; // captured below (no structured binding)
    auto onDisc = [&](double r, double a) {
        return project(pupilCentre + (bu * std::cos(a) + bv * std::sin(a)) * r);
    };
    constexpr int kOutline = 96;
    std::vector<cv::Point2d> pupilOutline, irisOutline;
    for (int i = 0; i < kOutline; ++i) {
        const double a = 2.0 * std::numbers::pi * i / kOutline;
        pupilOutline.push_back(onDisc(rp, a));
        irisOutline.push_back(onDisc(kIrisRadiusMm, a));
    }
    std::vector<cv::Point2f> fitPoints(pupilOutline.begin(), pupilOutline.end());
    const cv::RotatedRect pupilEllipse = cv::fitEllipse(fitPoints);
    const cv::Point2d centre(pupilEllipse.center.x, pupilEllipse.center.y);
    const cv::Point2d eyeImage = project(eyeMm);
    auto toFixed = [](const std::vector<cv::Point2d>& pts) {
        std::vector<cv::Point> out;
        out.reserve(pts.size());
        for (const cv::Point2d& p : pts)
            out.push_back(fixed(p));
        return out;
    };

    // Eyelids: parabolas between the corners, fixed to the face (they move and turn with it when
    // the headset slips); the upper lid follows the vertical gaze and both meet on the lower
    // lid's line when the eye is shut.
    const double halfWidth = 125.0 * s;
    const double open = g.lidOpen;
    const double upper = (mConfig.upperLidHeight + 0.9 * (ang.y + mPitch0)) * s;
    const double lower = (50.0 - mConfig.lowerLidRaise) * s;
    const cv::Point2d corner(eyeImage.x, eyeImage.y + 8.0 * s);
    const double lidRoll = mRollDeg * 0.5 + faceRoll;
    auto lidY = [&](double u, bool isUpper) {
        const double bulge = 1.0 - u * u;
        const double up = -upper * open + lower * (1.0 - open);
        return corner.y + (isUpper ? up : lower) * bulge;
    };
    auto lidPoint = [&](double u, bool isUpper) {
        return rotate(cv::Point2d(u * halfWidth, lidY(u, isUpper) - corner.y), lidRoll) + corner;
    };
    std::vector<cv::Point> opening;
    constexpr int kLidSteps = 48;
    for (int i = 0; i <= kLidSteps; ++i)
        opening.push_back(fixed(lidPoint(-1.0 + 2.0 * i / kLidSteps, true)));
    for (int i = kLidSteps; i >= 0; --i)
        opening.push_back(fixed(lidPoint(-1.0 + 2.0 * i / kLidSteps, false)));

    // The eye layer: sclera, iris (texture of radial fibres and a dark limbus), pupil, glints.
    cv::Mat eye = mSclera.clone();
    const std::vector<std::vector<cv::Point>> irisPoly{toFixed(irisOutline)};
    cv::fillPoly(eye, irisPoly, cv::Scalar(mIrisLevel), cv::LINE_AA, kShift);
    for (int k = 0; k < 40; ++k) {
        const double a = k * 9.0 * kDeg;
        const int level = mIrisLevel + ((k * 37) % 23) - 11;
        cv::line(eye, fixed(onDisc(rp * 1.1, a)), fixed(onDisc(kIrisRadiusMm * 0.92, a)),
                 cv::Scalar(std::max(0, level)), 2, cv::LINE_AA, kShift);
    }
    cv::polylines(eye, irisPoly, true, cv::Scalar(std::max(0, mIrisLevel - 45)),
                  static_cast<int>(3 * s * kSuper), cv::LINE_AA, kShift);
    const std::vector<std::vector<cv::Point>> pupilPoly{toFixed(pupilOutline)};
    cv::fillPoly(eye, pupilPoly, cv::Scalar(mPupilLevel), cv::LINE_AA, kShift);
    // Corneal glints: where the corneal sphere's normal halves the angle between the light and
    // the camera (the camera's direction is -z for the orthographic camera).
    const cv::Vec3d cornea = eyeMm + gaze * kCorneaOffsetMm;
    const cv::Vec3d toViewer =
        mConfig.perspective ? cv::normalize(-cornea) : cv::Vec3d(0.0, 0.0, -1.0);
    const double irisPx = cv::norm(irisOutline.front() - centre);
    for (const cv::Vec3d& light : mLights) {
        const cv::Vec3d n = cv::normalize(cv::normalize(light - cornea) + toViewer);
        const cv::Point2d p = project(cornea + n * kCorneaRadiusMm);
        if (cv::norm(p - centre) > irisPx * 0.95) continue; // glints only on the cornea
        cv::circle(eye, fixed(p), fixedLength(2.0 * s), cv::Scalar(250), cv::FILLED, cv::LINE_AA,
                   kShift);
    }
    for (const double a : mBorderGlintAngles) {
        cv::circle(eye, fixed(onDisc(rp, a)), fixedLength(1.8 * s), cv::Scalar(245), cv::FILLED,
                   cv::LINE_AA, kShift);
    }

    cv::Mat openingMask = cv::Mat::zeros(eye.size(), CV_8U);
    cv::fillPoly(openingMask, std::vector<std::vector<cv::Point>>{opening}, cv::Scalar(255),
                 cv::LINE_8, kShift);
    cv::Mat canvas = mSkin.clone();
    eye.copyTo(canvas, openingMask);

    // Lid margins, make-up and lashes on top.
    std::vector<cv::Point> margin(opening.begin(), opening.begin() + kLidSteps + 1);
    if (mConfig.eyeliner) {
        // Eyeliner darker than the pupil, just above the margin.
        std::vector<cv::Point> liner;
        for (int i = 0; i <= kLidSteps; ++i) {
            const double u = -0.9 + 1.8 * i / kLidSteps;
            liner.push_back(fixed(lidPoint(u, true) + cv::Point2d(0.0, -3.0 * s)));
        }
        cv::polylines(canvas, liner, false, cv::Scalar(std::max(2, mPupilLevel - 12)),
                      static_cast<int>(5 * s * kSuper), cv::LINE_AA, kShift);
    }
    cv::polylines(canvas, margin, false, cv::Scalar(mLashLevel + 30),
                  static_cast<int>(2 * s * kSuper), cv::LINE_AA, kShift);
    for (const Lash& l : mLashes) {
        const cv::Point2d base = lidPoint(l.u, true);
        const double len = l.length * s;
        const cv::Point2d dir =
            l.droops ? cv::Point2d(0.35 * l.u, 1.0) : cv::Point2d(0.8 * l.u, -1.0);
        const cv::Point2d side(-dir.y, dir.x);
        std::vector<cv::Point> pts;
        for (int i = 0; i <= 4; ++i) {
            const double v = i / 4.0;
            pts.push_back(fixed(base + dir * (len * v) + side * (l.bend * len * v * v)));
        }
        const int width = l.mascara ? static_cast<int>(std::lround(s * kSuper * 2.6))
                                    : std::max(1, static_cast<int>(std::lround(s * kSuper * 0.75)));
        const int level = l.mascara ? std::max(2, mPupilLevel - 10) : mLashLevel;
        cv::polylines(canvas, pts, false, cv::Scalar(level), width, cv::LINE_AA, kShift);
    }

    cv::Mat image;
    cv::resize(canvas, image, mConfig.size, 0, 0, cv::INTER_AREA);
    if (mConfig.blurSigma > 0.0) cv::GaussianBlur(image, image, cv::Size(), mConfig.blurSigma * s);
    const double gain =
        1.0 + mConfig.exposureDrift * std::sin(2 * std::numbers::pi * tMs / 6000.0 + mPupilPhase);
    cv::Mat noisy;
    image.convertTo(noisy, CV_32F, gain);
    if (mConfig.noiseSigma > 0.0) {
        cv::Mat noise(image.size(), CV_32F);
        cv::RNG rng(mConfig.seed * 1000003ull + static_cast<std::uint64_t>(frame));
        rng.fill(noise, cv::RNG::NORMAL, 0.0, mConfig.noiseSigma);
        noisy += noise;
    }
    noisy.convertTo(image, CV_8U);

    if (truth) {
        // Visibility: pupil pixels inside the lid opening, counted on the 2x canvas.
        cv::Mat pupilMask = cv::Mat::zeros(eye.size(), CV_8U);
        cv::fillPoly(pupilMask, pupilPoly, cv::Scalar(255), cv::LINE_8, kShift);
        const int total = cv::countNonZero(pupilMask);
        cv::Mat visible;
        cv::bitwise_and(pupilMask, openingMask, visible);
        truth->frame = frame;
        truth->tMs = tMs;
        truth->centre = centre;
        const bool wide = pupilEllipse.size.width >= pupilEllipse.size.height;
        truth->axisA = 0.5 * std::max(pupilEllipse.size.width, pupilEllipse.size.height);
        truth->axisB = 0.5 * std::min(pupilEllipse.size.width, pupilEllipse.size.height);
        const double major = wide ? pupilEllipse.angle : pupilEllipse.angle + 90.0;
        truth->angleDeg = std::fmod(std::fmod(major, 180.0) + 180.0, 180.0);
        truth->visibility =
            total > 0 ? cv::countNonZero(visible) / static_cast<double>(total) : 0.0;
        // The eye's rotation against the camera axis (yaw right, pitch up in the image).
        truth->yawDeg = std::atan2(-gaze[0], -gaze[2]) / kDeg;
        truth->pitchDeg = std::asin(std::clamp(-gaze[1], -1.0, 1.0)) / kDeg;
        truth->gaze = g;
        truth->eyeCentreMm = eyeMm;
        truth->gazeDirection = gaze;
        truth->pupilRadiusMm = rp;
        truth->fixationMm = fixation;
    }
    return image;
}

} // namespace gt::eyetrack
