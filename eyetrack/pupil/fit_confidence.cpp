#include "pupil/fit_confidence.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "pupil/image_sampling.hpp"

namespace gt::eyetrack::starburst {

namespace {

// The far end of the sharpness test's wide band outside an outline point p (unit normal n): the
// grey level `wide` px out, or the last level before the profile rises past 3x the edge's own
// step (in -> out) — a second edge. A pupil whose iris is a thin ring (a large pupil, a dark
// iris seen close) has the iris/sclera boundary within 0.3 of its minor axis, and the wide step
// would measure the sclera and call the crisp pupil edge a shadow's. A shadow's or a smudge's
// ramp keeps rising about as fast as within the edge, so it reaches 3x only past the band.
// -1 when the band leaves the image; a glint at its far end: `out` (the band ends at the edge).
double wideOutside(const cv::Mat& grey, cv::Point2d p, cv::Point2d n, double d, double wide,
                   double in, double out, const RayLevels& lv) {
    const double far = sample(grey, p.x + wide * n.x, p.y + wide * n.y);
    if (far < 0.0) {
        return -1.0;
    }
    const double secondEdge = in + 3.0 * (out - in);
    double last = out;
    for (double t = d + 1.0; t <= wide; t += 1.0) {
        const double w = sample(grey, p.x + t * n.x, p.y + t * n.y);
        if (w < 0.0 || w >= lv.glint || w > secondEdge) {
            break;
        }
        last = w;
    }
    return far >= lv.glint ? out : std::max(out, std::min(far, last));
}

} // namespace

OutlineSupport outlineSupport(const cv::Mat& grey, const cv::RotatedRect& e, const RayLevels& lv) {
    constexpr int kSamples = 48;
    const double minor = std::min(e.size.width, e.size.height);
    const double d = std::max(1.5, 0.06 * minor);
    // Sharpness: the step across d against the step across a wider band. A pupil's edge is a
    // step blurred by the optics (~0.6 or more of the wide step within 1.5 px); a shadow on the
    // skin or a make-up smudge is blurred over many pixels (~0.3).
    const double wide = std::max(d + 2.5, 0.3 * minor);
    const double need = 0.3 * (lv.surround - lv.pupil);
    int supported = 0, counted = 0, covered = 0;
    std::array<double, kSamples> ratios{};
    int nRatios = 0;
    forEachOutlinePoint(e, kSamples, [&](cv::Point2d p, cv::Point2d n) {
        const double in = sample(grey, p.x - d * n.x, p.y - d * n.y);
        const double out = sample(grey, p.x + d * n.x, p.y + d * n.y);
        if (in < 0.0 || out < 0.0) {
            ++counted; // outside the image: unsupported
            return;
        }
        if (out >= lv.glint) return; // a glint on the boundary: neither for nor against
        ++counted;
        if (out - in > need && in < lv.threshold) {
            ++supported;
            const double wideIn = sample(grey, p.x - wide * n.x, p.y - wide * n.y);
            const double wideOut = wideOutside(grey, p, n, d, wide, in, out, lv);
            if (wideIn >= 0.0 && wideOut >= 0.0) {
                ratios[static_cast<std::size_t>(nRatios++)] =
                    (out - in) / std::max(out - in, wideOut - wideIn);
            }
        } else if (in >= lv.threshold && out >= lv.threshold) {
            ++covered;
        }
    });
    OutlineSupport s;
    if (nRatios > 0) {
        auto mid = ratios.begin() + nRatios / 2;
        std::nth_element(ratios.begin(), mid, ratios.begin() + nRatios);
        s.sharpness = *mid;
    }
    if (counted > 0) s.all = static_cast<double>(supported) / counted;
    // At least half the outline must be in view to be judged on the visible part alone.
    const int visible = counted - covered;
    s.visible =
        2 * visible >= counted && visible > 0 ? static_cast<double>(supported) / visible : s.all;
    return s;
}

double outsideLevel(const cv::Mat& grey, const cv::RotatedRect& e, const RayLevels& lv) {
    // Median grey level a few pixels outside the ellipse, glints excluded: the iris next to the
    // pupil, whatever lies further out.
    constexpr int kSamples = 48;
    const double d = std::max(2.5, 0.1 * std::min(e.size.width, e.size.height));
    std::vector<double> values;
    values.reserve(kSamples);
    forEachOutlinePoint(e, kSamples, [&](cv::Point2d p, cv::Point2d n) {
        const double out = sample(grey, p.x + d * n.x, p.y + d * n.y);
        if (out >= 0.0 && out < lv.glint) values.push_back(out);
    });
    if (values.size() < kSamples / 4) return -1.0;
    std::nth_element(values.begin(),
                     values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
    return values[values.size() / 2];
}

Interior interiorFill(const cv::Mat& grey, const cv::RotatedRect& e, const RayLevels& lv) {
    const double th = e.angle * std::numbers::pi / 180.0;
    const cv::Point2d u(std::cos(th), std::sin(th)), v(-std::sin(th), std::cos(th));
    const double a = 0.5 * e.size.width, b = 0.5 * e.size.height;
    const cv::Point2d c(e.center.x, e.center.y);
    std::array<double, 49> values{};
    int n = 0, dark = 0;
    auto add = [&](cv::Point2d p) {
        const double g = sample(grey, p.x, p.y);
        if (g < 0.0 || g >= lv.glint) return; // off the image, or a glint
        values[static_cast<std::size_t>(n++)] = g;
        if (g < lv.threshold) ++dark;
    };
    add(c);
    for (const double r : {0.3, 0.55, 0.8}) {
        for (int k = 0; k < 16; ++k) {
            const double phi = (k + 0.5 * r) * 2.0 * std::numbers::pi / 16.0;
            add(c + u * (r * a * std::cos(phi)) + v * (r * b * std::sin(phi)));
        }
    }
    if (n == 0) return {0.0, 255.0, 255.0};
    std::sort(values.begin(), values.begin() + n);
    return {static_cast<double>(dark) / n, values[static_cast<std::size_t>(n / 2)],
            values[static_cast<std::size_t>(3 * n / 4)]};
}

double medianBeyond(const cv::Mat& grey, const cv::RotatedRect& e, const cv::RotatedRect& inner,
                    double glint) {
    const auto axes = [](const cv::RotatedRect& r) {
        const double th = r.angle * std::numbers::pi / 180.0;
        return std::pair{cv::Point2d(std::cos(th), std::sin(th)),
                         cv::Point2d(-std::sin(th), std::cos(th))};
    };
    const auto [u, v] = axes(e);
    const auto [ui, vi] = axes(inner);
    const double a = 0.5 * e.size.width, b = 0.5 * e.size.height;
    const double ai = 0.5 * inner.size.width, bi = 0.5 * inner.size.height;
    const cv::Point2d c(e.center.x, e.center.y), ci(inner.center.x, inner.center.y);
    constexpr int kPerRing = 32;
    std::array<double, 3 * kPerRing> values{};
    std::size_t n = 0;
    for (const double r : {0.3, 0.55, 0.8}) {
        for (int k = 0; k < kPerRing; ++k) {
            const double phi = (k + 0.5) * 2.0 * std::numbers::pi / kPerRing;
            const cv::Point2d q = c + u * (r * a * std::cos(phi)) + v * (r * b * std::sin(phi));
            const cv::Point2d d = q - ci;
            const double x = d.dot(ui) / ai, y = d.dot(vi) / bi;
            if (x * x + y * y <= 1.1) {
                continue; // inside `inner` or on its outline
            }
            const double g = sample(grey, q.x, q.y);
            if (g >= 0.0 && g < glint) {
                values[n++] = g;
            }
        }
    }
    if (n < 4) {
        return -1.0;
    }
    const auto mid = values.begin() + static_cast<std::ptrdiff_t>(n / 2);
    std::nth_element(values.begin(), mid, values.begin() + static_cast<std::ptrdiff_t>(n));
    return *mid;
}

double sizeConsistency(double semiMajor, double recentRadius) {
    if (recentRadius <= 0.0) return 1.0;
    const double l = std::log(semiMajor / recentRadius);
    constexpr double kSigma = 0.35; // a 1.4x size change keeps 60 % of the confidence
    return std::exp(-0.5 * l * l / (kSigma * kSigma));
}

double roundAxisRatio(double configured, double flattest, double eyeRatioMargin, double eyeRatio) {
    // A camera at a steep angle sees every pupil of its eye flat: the ramp's round end follows
    // the eye's own pupil, so those pupils keep their confidence and slivers under the lid of an
    // eye seen head-on gain none.
    double round = configured;
    if (eyeRatioMargin > 0.0 && eyeRatio > 0.0) {
        // Never rounder than the configured end, nor within 0.1 of the flat one (a min/max, not
        // std::clamp: a configuration may set the two ends closer than that).
        round = std::max(flattest + 0.1, std::min(round, eyeRatio - eyeRatioMargin));
    }
    return round;
}

FitEvidence judgeFit(const cv::Mat& grey, const cv::RotatedRect& e, const RayLevels& lv,
                     double flattest, double round) {
    FitEvidence ev;
    const OutlineSupport support = outlineSupport(grey, e, lv);
    const auto [fill, interior, interiorHigh] = interiorFill(grey, e, lv);
    // What makes a dark ellipse a pupil besides its outline: a crisp edge (not a shadow or a
    // smudge of make-up) and a filled dark inside (not a cluster of lashes with bright gaps).
    const double sharp = smoothstep(0.3, 0.55, support.sharpness);
    ev.quality = sharp * smoothstep(0.35, 0.75, fill);
    ev.interior = interior;
    ev.interiorHigh = interiorHigh;
    ev.outside = outsideLevel(grey, e, lv);
    // The visible outline's support in full, times the whole outline's to the power 1/4: a lid
    // over part of a well-fitted pupil still lowers the confidence, but less than an even
    // geometric mean would, which put most right answers on pupils 50-80 % visible below the gaze
    // filter's gate. The inside's share of dark samples ramps over 0.3-0.7: the wrong answers
    // that pass the gate are irises and slivers of a covered pupil, dark throughout, while a
    // right answer on a pupil whose top is under the lid has lid skin in its upper samples.
    ev.confidence =
        std::pow(support.all, 0.25) * support.visible * sharp * smoothstep(0.3, 0.7, fill);
    // A plausible shape for the camera (StarburstConfig::flattestAxisRatio): the wrong answers
    // that pass the gate are mostly slivers, the visible part of a pupil under the lid fitted as
    // a flat ellipse (axis ratio 0.4-0.6), while the pupils in view are mostly 0.75 or rounder.
    const cv::Size2f axes = e.size;
    const double axisRatio =
        std::min(axes.width, axes.height) / std::max(1e-6F, std::max(axes.width, axes.height));
    ev.shapeFactor = smoothstep(flattest, round, axisRatio);
    ev.confidence *= ev.shapeFactor;
    ev.supportAll = support.all;
    ev.visibleSupport = support.visible;
    ev.fill = fill;
    ev.axisRatio = axisRatio;
    return ev;
}

} // namespace gt::eyetrack::starburst
