#include "pupil/pupil_shape_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gt::eyetrack {

namespace {

constexpr std::size_t kWindow = 300;      // samples kept (2.5 s at 120 Hz of whole pupils)
constexpr std::size_t kLeastSamples = 40; // before any prediction
constexpr std::size_t kRefitEvery = 10;   // samples between refits
// The minor-axis lines must cross at an angle: the smaller eigenvalue of their weighted normal
// matrix, over the total weight (0.5 when the directions are spread evenly, 0 when parallel).
constexpr double kLeastSpread = 0.05;
constexpr double kLeastTurn = 2.0;       // summed sin^2 theta: pupils seen clearly turned
constexpr double kMostRatioError = 0.05; // median |ratio - predicted| over the samples
constexpr double kMostAngleError = 10.0; // median major-axis turn, deg, over the flatter ones
constexpr double kFlatEnough = 0.9;      // samples whose major axis has a direction to check

} // namespace

void PupilShapeModel::reset() {
    mSamples.clear();
    mNext = 0;
    mAdded = 0;
    mReady = false;
    mCentre = {};
    mRadius = 0.0;
}

PupilShape shapeOf(const cv::RotatedRect& e) {
    const double w = e.size.width, h = e.size.height;
    return {std::min(w, h) / std::max(1e-6, std::max(w, h)), h > w ? e.angle + 90.0 : e.angle};
}

double axisTurnDeg(double aDeg, double bDeg) {
    return std::abs(std::remainder(aDeg - bDeg, 180.0));
}

void PupilShapeModel::add(const cv::RotatedRect& e) {
    if (!(e.size.width > 0.0F && e.size.height > 0.0F)) {
        return;
    }
    const PupilShape shape = shapeOf(e);
    const double angle = shape.majorAngleDeg * std::numbers::pi / 180.0;
    const Sample s{{e.center.x, e.center.y}, shape.axisRatio, {std::cos(angle), std::sin(angle)}};
    if (mSamples.size() < kWindow) {
        mSamples.push_back(s);
    } else {
        mSamples[mNext] = s;
    }
    mNext = (mNext + 1) % kWindow;
    if (++mAdded % kRefitEvery == 0) {
        refit();
    }
}

void PupilShapeModel::refit() {
    mReady = false;
    if (mSamples.size() < kLeastSamples) {
        return;
    }
    // The eyeball centre c lies on every minor axis: major . (c - p) = 0, weighted by sin^2.
    double a00 = 0.0, a01 = 0.0, a11 = 0.0, b0 = 0.0, b1 = 0.0, total = 0.0;
    for (const Sample& s : mSamples) {
        const double w = 1.0 - s.ratio * s.ratio;
        const cv::Point2d u = s.major;
        const double up = u.x * s.centre.x + u.y * s.centre.y;
        a00 += w * u.x * u.x;
        a01 += w * u.x * u.y;
        a11 += w * u.y * u.y;
        b0 += w * u.x * up;
        b1 += w * u.y * up;
        total += w;
    }
    if (total < kLeastTurn) {
        return;
    }
    const double det = a00 * a11 - a01 * a01;
    const double mean = 0.5 * (a00 + a11);
    const double spread = mean - std::sqrt(std::max(0.0, mean * mean - det));
    if (spread < kLeastSpread * total || det <= 0.0) {
        return;
    }
    const cv::Point2d c((b0 * a11 - b1 * a01) / det, (a00 * b1 - a01 * b0) / det);
    // R from |p - c| = R sin(theta).
    double num = 0.0, den = 0.0;
    for (const Sample& s : mSamples) {
        const double sine = std::sqrt(std::max(0.0, 1.0 - s.ratio * s.ratio));
        num += cv::norm(s.centre - c) * sine;
        den += sine * sine;
    }
    if (den <= 0.0 || num <= 0.0) {
        return;
    }
    mCentre = c;
    mRadius = num / den;
    // It must explain what it learnt from: the ratios and the directions of the major axes.
    std::vector<double> ratioErrors, angleErrors;
    ratioErrors.reserve(mSamples.size());
    mReady = true;
    for (const Sample& s : mSamples) {
        const PupilShape shape = *predict(s.centre);
        ratioErrors.push_back(std::abs(shape.axisRatio - s.ratio));
        if (s.ratio < kFlatEnough) {
            const double a = shape.majorAngleDeg * std::numbers::pi / 180.0;
            const double along = std::abs(s.major.x * std::cos(a) + s.major.y * std::sin(a));
            angleErrors.push_back(std::acos(std::min(1.0, along)) * 180.0 / std::numbers::pi);
        }
    }
    const auto median = [](std::vector<double>& v) {
        const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
        std::nth_element(v.begin(), mid, v.end());
        return *mid;
    };
    mReady = median(ratioErrors) <= kMostRatioError &&
             (angleErrors.empty() || median(angleErrors) <= kMostAngleError);
}

std::optional<PupilShape> PupilShapeModel::predict(cv::Point2d centre) const {
    if (!mReady) {
        return std::nullopt;
    }
    const cv::Point2d d = centre - mCentre;
    const double dist = cv::norm(d);
    const double sine = std::min(0.99, dist / mRadius);
    PupilShape shape;
    shape.axisRatio = std::sqrt(1.0 - sine * sine);
    // The major axis is across the line from the eyeball centre's image.
    shape.majorAngleDeg = dist > 1e-9 ? std::atan2(d.x, -d.y) * 180.0 / std::numbers::pi : 0.0;
    return shape;
}

} // namespace gt::eyetrack
