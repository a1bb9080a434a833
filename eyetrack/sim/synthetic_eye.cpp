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

} // namespace

void applyPreset(EyeSimConfig& c, const std::string& preset) {
    if (preset == "clean") {
        c.glints = 1;
        c.blurSigma = 0.7;
        c.noiseSigma = 1.5;
        c.exposureDrift = 0.0;
        c.upperLidHeight = 82.0;
        c.droopingLashes = 0.0;
        c.schedule.blinks = false;
    } else if (preset == "hard") {
        c.glints = 4;
        c.blurSigma = 1.6;
        c.noiseSigma = 6.0;
        c.exposureDrift = 0.15;
        c.upperLidHeight = 36.0;
        c.droopingLashes = 0.3;
        c.schedule.blinks = true;
    } else {
        throw EyetrackError("unknown eyesim preset '" + preset + "' (clean | hard)");
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
    std::mt19937_64 rng(mConfig.seed * 0xD1B54A32D192ED03ull + 5);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    auto range = [&](double a, double b) { return a + (b - a) * uni(rng); };

    mScale = mConfig.size.height / 240.0;
    const double s = mScale;
    mEyeCentre = {0.5 * mConfig.size.width + range(-15, 15) * s,
                  0.5 * mConfig.size.height + range(-8, 8) * s};
    // The camera sits below and to one side of the screen: looking at the screen centre the eye
    // is rotated up and sideways relative to the camera axis, and the image is rolled.
    mYaw0 = range(-6, 6);
    mPitch0 = range(2, 10);
    mRollDeg = range(-8, 8);
    mPupilRadius = range(15, 24) * s;
    mPupilPhase = range(0, 2 * std::numbers::pi);
    mPupilLevel = static_cast<int>(range(18, 36));
    mIrisLevel = static_cast<int>(range(95, 125));
    mLashLevel = static_cast<int>(range(30, 50));
    // Glint offsets from the corneal centre: lights on a ring around the camera, reflected on a
    // 7.8 mm corneal sphere (~70 px at 240 px): offset = rc * (L + z)_xy / |L + z|.
    const double rc = 70.0 * s;
    for (int i = 0; i < mConfig.glints; ++i) {
        const double a = (i * 90.0 + 45.0 + range(-10, 10)) * kDeg, tilt = range(12, 20) * kDeg;
        const cv::Vec3d l(std::sin(tilt) * std::cos(a), std::sin(tilt) * std::sin(a),
                          std::cos(tilt));
        const cv::Vec3d h = cv::normalize(l + cv::Vec3d(0, 0, 1));
        mGlintOffsets.emplace_back(rc * h[0], rc * h[1]);
    }
    const int lashes = static_cast<int>(range(35, 60));
    for (int i = 0; i < lashes; ++i) {
        const bool droops = uni(rng) < mConfig.droopingLashes;
        mLashes.push_back(
            {range(-0.85, 0.85), range(9, 18) * (droops ? 1.3 : 1.0), range(-0.6, 0.6), droops});
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
    mSkin.convertTo(mSkin, CV_8U);
    mSclera.convertTo(mSclera, CV_8U);
}

cv::Mat SyntheticEye::render(int frame, EyeTruth* truth) const {
    const double s = mScale;
    const double tMs = frameTimeMs(frame);
    const GazeState g = mSchedule.at(tMs);
    const cv::Point2d ang = mConfig.schedule.display.anglesDeg(g.gaze);
    const double yaw = (ang.x + mYaw0) * kDeg, pitch = (ang.y + mPitch0) * kDeg;
    // Optical axis in camera coordinates (x right, y down, z towards the camera).
    const cv::Vec3d axis(std::sin(yaw) * std::cos(pitch), -std::sin(pitch),
                         std::cos(yaw) * std::cos(pitch));
    const cv::Point2d radial = rotate({axis[0], axis[1]}, mRollDeg);
    const double cosTheta = axis[2];

    const double pupilPlane = 100.0 * s; // ~11 mm from the rotation centre at 240 px
    const cv::Point2d centre = mEyeCentre + radial * pupilPlane;
    const double rp =
        mPupilRadius * (1.0 + 0.08 * std::sin(2 * std::numbers::pi * tMs / 4000.0 + mPupilPhase));
    const double ri = 46.0 * s;
    const double majorDeg = std::atan2(radial.y, radial.x) / kDeg + 90.0;

    // Eyelids: parabolas between the corners; the upper lid follows the vertical gaze and both
    // meet on the lower lid's line when the eye is shut.
    const double halfWidth = 125.0 * s;
    const double open = g.lidOpen;
    const double upper = (mConfig.upperLidHeight + 0.9 * (ang.y + mPitch0)) * s;
    const double lower = 50.0 * s;
    const cv::Point2d corner(mEyeCentre.x, mEyeCentre.y + 8.0 * s);
    auto lidY = [&](double u, bool isUpper) {
        const double bulge = 1.0 - u * u;
        const double up = -upper * open + lower * (1.0 - open);
        return corner.y + (isUpper ? up : lower) * bulge;
    };
    auto lidPoint = [&](double u, bool isUpper) {
        return rotate(cv::Point2d(u * halfWidth, lidY(u, isUpper) - corner.y), mRollDeg * 0.5) +
               corner;
    };
    std::vector<cv::Point> opening;
    constexpr int kLidSteps = 48;
    for (int i = 0; i <= kLidSteps; ++i)
        opening.push_back(fixed(lidPoint(-1.0 + 2.0 * i / kLidSteps, true)));
    for (int i = kLidSteps; i >= 0; --i)
        opening.push_back(fixed(lidPoint(-1.0 + 2.0 * i / kLidSteps, false)));

    // The eye layer: sclera, iris (texture of radial fibres and a dark limbus), pupil, glints.
    cv::Mat eye = mSclera.clone();
    const cv::Point c = fixed(centre);
    const double irisAngle = majorDeg;
    cv::ellipse(eye, c, {fixedLength(ri), fixedLength(ri * cosTheta)}, irisAngle, 0, 360,
                cv::Scalar(mIrisLevel), cv::FILLED, cv::LINE_AA, kShift);
    for (int k = 0; k < 40; ++k) {
        const double a = k * 9.0 * kDeg;
        auto onIris = [&](double r) {
            const cv::Point2d local(r * std::cos(a), r * cosTheta * std::sin(a));
            return centre + rotate(local, irisAngle);
        };
        const int level = mIrisLevel + ((k * 37) % 23) - 11;
        cv::line(eye, fixed(onIris(rp * 1.1)), fixed(onIris(ri * 0.92)), cv::Scalar(level), 2,
                 cv::LINE_AA, kShift);
    }
    cv::ellipse(eye, c, {fixedLength(ri), fixedLength(ri * cosTheta)}, irisAngle, 0, 360,
                cv::Scalar(std::max(0, mIrisLevel - 45)), static_cast<int>(3 * s * kSuper),
                cv::LINE_AA, kShift);
    cv::ellipse(eye, c, {fixedLength(rp), fixedLength(rp * cosTheta)}, majorDeg, 0, 360,
                cv::Scalar(mPupilLevel), cv::FILLED, cv::LINE_AA, kShift);
    const cv::Point2d cornea = mEyeCentre + radial * (0.5 * pupilPlane);
    for (const cv::Point2d& off : mGlintOffsets) {
        const cv::Point2d p = cornea + off;
        if (cv::norm(p - centre) > ri * 0.95) continue; // glints only on the cornea
        cv::circle(eye, fixed(p), fixedLength(2.0 * s), cv::Scalar(250), cv::FILLED, cv::LINE_AA,
                   kShift);
    }

    cv::Mat openingMask = cv::Mat::zeros(eye.size(), CV_8U);
    cv::fillPoly(openingMask, std::vector<std::vector<cv::Point>>{opening}, cv::Scalar(255),
                 cv::LINE_8, kShift);
    cv::Mat canvas = mSkin.clone();
    eye.copyTo(canvas, openingMask);

    // Lid margins and lashes on top.
    std::vector<cv::Point> margin(opening.begin(), opening.begin() + kLidSteps + 1);
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
        cv::polylines(canvas, pts, false, cv::Scalar(mLashLevel),
                      std::max(1, static_cast<int>(std::lround(s * kSuper * 0.75))), cv::LINE_AA,
                      kShift);
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
        cv::ellipse(pupilMask, c, {fixedLength(rp), fixedLength(rp * cosTheta)}, majorDeg, 0, 360,
                    cv::Scalar(255), cv::FILLED, cv::LINE_8, kShift);
        const int total = cv::countNonZero(pupilMask);
        cv::Mat visible;
        cv::bitwise_and(pupilMask, openingMask, visible);
        truth->frame = frame;
        truth->tMs = tMs;
        truth->centre = centre;
        truth->axisA = rp;
        truth->axisB = rp * cosTheta;
        truth->angleDeg = std::fmod(majorDeg + 360.0, 180.0);
        truth->visibility =
            total > 0 ? cv::countNonZero(visible) / static_cast<double>(total) : 0.0;
        truth->yawDeg = yaw / kDeg;
        truth->pitchDeg = pitch / kDeg;
        truth->gaze = g;
    }
    return image;
}

} // namespace gt::eyetrack
