#include "gaze/binocular.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "error.hpp"

namespace gt::eyetrack {

namespace {

cv::Vec3d onScreenCm(const DisplayGeometry& d, cv::Point2d px) {
    const double k = d.cmPerPixel();
    return {(px.x - 0.5 * d.widthPx) * k, (px.y - 0.5 * d.heightPx) * k, d.distanceCm};
}

} // namespace

std::optional<Vergence> vergenceOf(const DisplayGeometry& d, double ipdMm, cv::Point2d left,
                                   cv::Point2d right) {
    const double ipd = 0.1 * ipdMm;
    const cv::Vec3d l = onScreenCm(d, left), r = onScreenCm(d, right);
    const cv::Vec3d eyeL(-0.5 * ipd, 0.0, 0.0), eyeR(0.5 * ipd, 0.0, 0.0);
    const cv::Vec3d a = cv::normalize(l - eyeL), b = cv::normalize(r - eyeR);
    Vergence v;
    v.angleDeg = std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180.0 / std::numbers::pi;
    const double denominator = ipd + l[0] - r[0];
    if (denominator < -1e-9) {
        return std::nullopt; // diverging lines of sight
    }
    v.distanceCm = denominator <= 1e-9 ? std::numeric_limits<double>::infinity()
                                       : d.distanceCm * ipd / denominator;
    return v;
}

cv::Point2d eyeAnglesDeg(const DisplayGeometry& d, double ipdMm, Eye eye, cv::Point2d px) {
    const double x0 = (eye == Eye::Left ? -0.05 : 0.05) * ipdMm;
    const cv::Vec3d p = onScreenCm(d, px) - cv::Vec3d(x0, 0.0, 0.0);
    const double yaw = std::atan2(p[0], p[2]);
    const double pitch = std::atan2(-p[1], std::hypot(p[0], p[2]));
    return {yaw * 180.0 / std::numbers::pi, pitch * 180.0 / std::numbers::pi};
}

BinocularCombiner::BinocularCombiner(DisplayGeometry display, double ipdMm, double maxSkewMs)
    : mDisplay(display), mIpdMm(ipdMm), mMaxSkewMs(maxSkewMs) {
    if (!(ipdMm > 30.0 && ipdMm < 90.0)) {
        throw EyetrackError("binocular: the interpupillary distance must be 30-90 mm");
    }
    if (!(maxSkewMs > 0.0)) {
        throw EyetrackError("binocular: the pairing window must be positive");
    }
}

BinocularSample BinocularCombiner::push(Eye eye, const GazeSample& s) {
    const auto self = static_cast<std::size_t>(eye), other = 1 - self;
    mLatest[self] = s;
    BinocularSample out;
    out.combined = s;
    (eye == Eye::Left ? out.left : out.right) = s;
    const auto& partner = mLatest[other];
    if (!partner || std::abs(partner->tMs - s.tMs) > mMaxSkewMs) {
        return out;
    }
    (eye == Eye::Left ? out.right : out.left) = *partner;
    const bool bothValid = isValid(s) && isValid(*partner) && s.event != GazeEvent::Blink &&
                           partner->event != GazeEvent::Blink;
    if (!bothValid) {
        // One eye lost or blinking: the other's gaze alone.
        if (!isValid(s) || s.event == GazeEvent::Blink) {
            out.combined = *partner;
        }
        out.combined.tMs = s.tMs;
        return out;
    }
    out.combined.x = 0.5f * (s.x + partner->x);
    out.combined.y = 0.5f * (s.y + partner->y);
    out.combined.confidence = std::min(s.confidence, partner->confidence);
    out.combined.saccade = s.saccade || partner->saccade;
    if (s.event == GazeEvent::Fixation && partner->event == GazeEvent::Fixation) {
        const GazeSample& l = *out.left;
        const GazeSample& r = *out.right;
        out.vergence = vergenceOf(mDisplay, mIpdMm, {l.x, l.y}, {r.x, r.y});
    }
    return out;
}

} // namespace gt::eyetrack
