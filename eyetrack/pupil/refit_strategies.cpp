#include "pupil/refit_strategies.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "pupil/fit_confidence.hpp"
#include "pupil/limbus_fit.hpp"

namespace gt::eyetrack::starburst {

namespace {

// A lid's margin among the edge points: the points on it, and the line's unit normal towards the
// pupil's centre and offset (normal . p = offset on the line).
struct LidLine {
    std::vector<int> points;
    cv::Point2d normal;
    double offset = 0.0;
};

// The lid test: a straight run of at least 8 edge points within 1 px of one line, spanning 1.4
// semi-minor axes or more (a pupil's own arc that long bends 3 px or more away from its chord),
// within 30 deg of the image's horizontal and not through the ellipse e's middle.
LidLine findLidLine(std::span<const cv::Point2d> points, const cv::RotatedRect& e) {
    const std::size_t n = points.size();
    const double semiMinor = 0.5 * std::min(e.size.width, e.size.height);
    const cv::Point2d centre(e.center.x, e.center.y);
    // Rays are cast in angle order, so a lid's points are neighbours: try the line through
    // every point and the one a few rays on, and follow it both ways while at most two points in
    // a row stray from it.
    constexpr std::size_t kStep = 6;
    constexpr int kMaxMisses = 2;
    LidLine best;
    std::vector<int> in;
    const int count = static_cast<int>(n);
    for (std::size_t i = 0; i < n; ++i) {
        const cv::Point2d a = points[i], b = points[(i + kStep) % n];
        cv::Point2d dir = b - a;
        const double len = cv::norm(dir);
        if (len < 4.0) {
            continue;
        }
        dir *= 1.0 / len;
        if (std::abs(dir.y) > 0.5) {
            continue; // a lid runs roughly across the image
        }
        const cv::Point2d normal(-dir.y, dir.x);
        const double offset = normal.dot(a);
        const double centreSide = normal.dot(centre) - offset;
        if (std::abs(centreSide) < 0.3 * semiMinor) {
            continue; // a chord through the middle
        }
        in.clear();
        double lo = 1e9, hi = -1e9;
        auto follow = [&](int from, int step) {
            int misses = 0;
            for (int k = 0; k < count && misses <= kMaxMisses; ++k) {
                const int j = ((from + step * k) % count + count) % count;
                const cv::Point2d q = points[static_cast<std::size_t>(j)];
                if (std::abs(normal.dot(q) - offset) > 1.0) {
                    ++misses;
                    continue;
                }
                misses = 0;
                in.push_back(j);
                const double t = dir.dot(q);
                lo = std::min(lo, t);
                hi = std::max(hi, t);
            }
        };
        follow(static_cast<int>(i), 1);
        follow(static_cast<int>(i) - 1, -1);
        if (in.size() >= 8 && in.size() < n && hi - lo >= 1.4 * semiMinor &&
            in.size() > best.points.size()) {
            best.points = in;
            best.normal = centreSide > 0.0 ? normal : -normal; // towards the pupil's centre
            best.offset = centreSide > 0.0 ? offset : -offset;
        }
    }
    return best;
}

// Whether `larger`, a refit of `fit` reaching under a lid, is taken: it keeps `keptInliers` of
// fit's inliers, its visible outline is about as well supported, and what it adds to fit lies
// under something brighter than the iris (the lid).
bool addsOnlyLid(const RefitContext& ctx, const EllipseFit& larger, const EllipseFit& fit,
                 double keptInliers) {
    const cv::Mat& grey = ctx.grey;
    const RayLevels& lv = ctx.levels;
    constexpr double kSupportMargin = 0.1; // visible support it may lose
    if (static_cast<double>(larger.inliers.size()) <
        keptInliers * static_cast<double>(fit.inliers.size())) {
        return false;
    }
    if (outlineSupport(grey, larger.ellipse, lv).visible <
        outlineSupport(grey, fit.ellipse, lv).visible - kSupportMargin) {
        return false;
    }
    const double added = medianBeyond(grey, larger.ellipse, fit.ellipse, lv.glint);
    return added >= lv.surround + kSkinAboveIris * (lv.surround - lv.pupil);
}

// The visible arc of fit e for the limbus refit: edge points on e whose gradient points out of
// it and not up (edges facing up are the lid's).
std::vector<cv::Point2d> visibleArc(const RefitContext& ctx, const cv::RotatedRect& e) {
    constexpr double kFacingUp = -0.7; // pupil edge points with gradient y below: the lid's
    constexpr double kOnFit = 1.5;     // px from the fit: a point of the visible arc
    const double th = e.angle * std::numbers::pi / 180.0, ct = std::cos(th), st = std::sin(th);
    const double ea = 0.5 * e.size.width, eb = 0.5 * e.size.height;
    std::vector<cv::Point2d> arc;
    for (std::size_t i = 0; i < ctx.points.size(); ++i) {
        const cv::Point2d q = ctx.points[i], g = ctx.gradients[i];
        if (g.y < kFacingUp) {
            continue;
        }
        const double dx = q.x - e.center.x, dy = q.y - e.center.y;
        const double u = dx * ct + dy * st, w = -dx * st + dy * ct;
        const double rho = std::sqrt(u * u / (ea * ea) + w * w / (eb * eb));
        const double len = std::sqrt(u * u + w * w);
        // On the fit, and its gradient pointing out of it.
        if (rho > 1e-9 && std::abs(len * (1.0 - 1.0 / rho)) <= kOnFit &&
            g.x * dx + g.y * dy >= 0.5 * len) {
            arc.push_back(q);
        }
    }
    return arc;
}

constexpr std::array kStrategies{
    RefitStrategy{"lid line", fitBesideLid},
    RefitStrategy{"recent size", fitAtRecentSize, 1, true},
    RefitStrategy{"under lid", fitUnderLid, 1, true},
    RefitStrategy{"rounder under lid", fitRounderUnderLid, 1, true},
    RefitStrategy{"eye shape", fitToEyeShape},
    RefitStrategy{"limbus", fitWithLimbus},
};

} // namespace

std::span<const RefitStrategy> refitStrategies() {
    return kStrategies;
}

Refitted applyRefits(const RefitContext& ctx, EllipseFit fit) {
    return applyRefits(ctx, std::move(fit), refitStrategies());
}

Refitted applyRefits(const RefitContext& ctx, EllipseFit fit,
                     std::span<const RefitStrategy> strategies) {
    const auto semiMajor = [](const EllipseFit& f) {
        return 0.5 * std::max(f.ellipse.size.width, f.ellipse.size.height);
    };
    Refitted out;
    bool sizeTaken = false;
    int refitted = 0; // the group whose alternative refitted
    for (const RefitStrategy& s : strategies) {
        if (s.heldToRecentSize && !sizeTaken) {
            out.fittedSemiMajor = semiMajor(fit);
            sizeTaken = true;
        }
        if (s.alternatives != 0 && s.alternatives == refitted) {
            continue;
        }
        if (auto refit = s.refit(ctx, fit)) {
            fit = std::move(*refit);
            refitted = s.alternatives;
        }
    }
    if (!sizeTaken) {
        out.fittedSemiMajor = semiMajor(fit);
    }
    out.fit = std::move(fit);
    return out;
}

// A lid over the pupil's top whose margin is lined with lashes as dark as the iris passes the ray
// walk's iris test: its edge points would make the fit hug the lid, centre low. They are dropped
// and the rest refitted; the refit counts only if its outline reaches at least 1 px beyond the
// line (the hidden arc) with its centre on the pupil's side.
std::optional<EllipseFit> fitBesideLid(const RefitContext& ctx, const EllipseFit& fit) {
    const std::size_t n = ctx.points.size();
    if (n < 20) {
        return std::nullopt;
    }
    LidLine line = findLidLine(ctx.points, fit.ellipse);
    if (line.points.empty()) {
        return std::nullopt;
    }
    std::sort(line.points.begin(), line.points.end());
    line.points.erase(std::unique(line.points.begin(), line.points.end()), line.points.end());
    std::vector<cv::Point2d> points, gradients;
    for (std::size_t j = 0, k = 0; j < n; ++j) {
        if (k < line.points.size() && line.points[k] == static_cast<int>(j)) {
            ++k;
            continue;
        }
        points.push_back(ctx.points[j]);
        gradients.push_back(ctx.gradients[j]);
    }
    if (points.size() < 12) {
        return std::nullopt;
    }
    // What is left is mostly the pupil's own outline: fewer RANSAC draws find it.
    RansacEllipseParams rest = ctx.ransac;
    rest.iterations = std::max(20, ctx.ransac.iterations / 3);
    auto refit = fitEllipseRansac(points, rest, gradients);
    if (!refit) {
        return std::nullopt;
    }
    // The pupil's hidden arc lies beyond the lid: the new outline must cross the line, and its
    // centre stay on the pupil's side.
    const cv::RotatedRect& f = refit->ellipse;
    const cv::Point2d fc(f.center.x, f.center.y);
    if (line.normal.dot(fc) - line.offset <= 0.0) {
        return std::nullopt;
    }
    double reach = 1e9;
    for (int k = 0; k < 36; ++k) {
        const double t = k * std::numbers::pi / 18.0, th = f.angle * std::numbers::pi / 180.0;
        const cv::Point2d q(f.center.x + 0.5 * f.size.width * std::cos(t) * std::cos(th) -
                                0.5 * f.size.height * std::sin(t) * std::sin(th),
                            f.center.y + 0.5 * f.size.width * std::cos(t) * std::sin(th) +
                                0.5 * f.size.height * std::sin(t) * std::cos(th));
        reach = std::min(reach, line.normal.dot(q) - line.offset);
    }
    if (reach > -1.0) {
        return std::nullopt;
    }
    return refit;
}

// Lashes hanging across the pupil's top are as dark as the pupil: rays run on through them and
// stop at their far side, and the fit grows over them, its centre high. When a fit is clearly
// larger than the pupil has lately been, the same edge points are fitted again within the recent
// size; that fit is taken when it keeps most of the inliers and its outline is about as well
// supported — a dilating pupil's larger fit is supported all round, a smaller ellipse inside it
// is not (a pupil growing while half under the lid, where the prior lags, keeps its size).
std::optional<EllipseFit> fitAtRecentSize(const RefitContext& ctx, const EllipseFit& fit) {
    const cv::Mat& grey = ctx.grey;
    const RayLevels& lv = ctx.levels;
    const RansacEllipseParams& rp = ctx.ransac;
    constexpr double kOversize = 1.15;     // fit semi-major over the recent radius
    constexpr double kSizedMax = 1.1;      // the refit's largest semi-axis, over the recent radius
    constexpr double kKeptInliers = 0.6;   // of the larger fit's
    constexpr double kSupportMargin = 0.1; // visible support it may lose
    if (ctx.priors.recentRadius <= 0.0) {
        return std::nullopt;
    }
    const double semiMajor = 0.5 * std::max(fit.ellipse.size.width, fit.ellipse.size.height);
    if (semiMajor <= kOversize * ctx.priors.recentRadius) {
        return std::nullopt;
    }
    RansacEllipseParams sized = rp;
    sized.maxAxis = 2.0 * kSizedMax * ctx.priors.recentRadius;
    sized.seed += 7;
    auto smaller = fitEllipseRansac(ctx.points, sized, ctx.gradients);
    if (!smaller || static_cast<double>(smaller->inliers.size()) <
                        kKeptInliers * static_cast<double>(fit.inliers.size())) {
        return std::nullopt;
    }
    const double larger = outlineSupport(grey, fit.ellipse, lv).visible;
    if (outlineSupport(grey, smaller->ellipse, lv).visible < larger - kSupportMargin) {
        return std::nullopt;
    }
    return smaller;
}

// A lid over the pupil's top whose margin is lined with lashes or eyeliner gives edge points that
// pass as the pupil's along a curve the lid-line test (fitBesideLid) does not take for a line;
// the fit then hugs the lid: as wide as the pupil, but its minor axis 0.5-0.8 of the pupil's and
// its centre low. When a fit about the recent pupil's size is much narrower than the recent
// pupil, the edge points are fitted again with the minor axis held near the recent one; that fit
// is taken when it keeps most of the inliers, its visible outline is about as well supported,
// and what it adds to the narrow fit is under something brighter than the iris (the lid): an eye
// turned away from the camera narrows its pupil too, but there the wider ellipse reaches into
// the iris.
std::optional<EllipseFit> fitUnderLid(const RefitContext& ctx, const EllipseFit& fit) {
    const RansacEllipseParams& rp = ctx.ransac;
    constexpr double kNarrow = 0.8;      // fit minor semi-axis over the recent one
    constexpr double kSameSize = 1.2;    // fit semi-major within this factor of the recent
    constexpr double kMinorFloor = 0.9;  // the refit's least minor semi-axis, over the recent
    constexpr double kLarger = 1.15;     // the refit's largest semi-axis, over the recent radius
    constexpr double kKeptInliers = 0.6; // of the narrow fit's
    if (ctx.priors.recentRadius <= 0.0 || ctx.priors.recentMinor <= 0.0) {
        return std::nullopt;
    }
    const double semiMajor = 0.5 * std::max(fit.ellipse.size.width, fit.ellipse.size.height);
    const double semiMinor = 0.5 * std::min(fit.ellipse.size.width, fit.ellipse.size.height);
    if (semiMinor >= kNarrow * ctx.priors.recentMinor ||
        std::abs(std::log(semiMajor / ctx.priors.recentRadius)) > std::log(kSameSize)) {
        return std::nullopt;
    }
    RansacEllipseParams wider = rp;
    wider.minAxis = 2.0 * kMinorFloor * ctx.priors.recentMinor;
    wider.maxAxis = std::max(wider.minAxis + 1.0, 2.0 * kLarger * ctx.priors.recentRadius);
    wider.seed += 11;
    auto fuller = fitEllipseRansac(ctx.points, wider, ctx.gradients);
    if (!fuller || !addsOnlyLid(ctx, *fuller, fit, kKeptInliers)) {
        return std::nullopt;
    }
    return fuller;
}

// fitUnderLid needs the recent pupil's size, which an eye whose pupil is never seen whole (the
// upper lid always over its top) never teaches: there the fit keeps hugging the lid, as wide as
// the pupil but flat, its centre low. Two things are known without the prior: the edges along a
// lid over the pupil's top face up (dark below, skin above), and a pupil seen by a head-mounted
// camera is seldom flatter than 0.7 (the eye's own ratio, once learnt, raises the bound). So a
// flatter fit is redone from the edge points that do not face up, held at least that round and
// about as wide; it is taken when it keeps half the inliers, moves up under the lid, keeps its
// visible outline about as well supported, and what it adds to the flat fit is brighter than the
// iris (the lid: a pupil flattened by the eye turning away would add iris).
std::optional<EllipseFit> fitRounderUnderLid(const RefitContext& ctx, const EllipseFit& fit) {
    const RansacEllipseParams& rp = ctx.ransac;
    constexpr double kRoundest = 0.7;    // the refit's least axis ratio (minor over major)
    constexpr double kEyeMargin = 0.1;   // or the eye's learnt ratio less this, if higher
    constexpr double kFacingUp = -0.7;   // edge points whose gradient's y is below are left out
    constexpr double kWider = 1.25;      // the refit's largest semi-axis, over the fit's
    constexpr double kKeptInliers = 0.5; // of the flat fit's
    const double semiMajor = 0.5 * std::max(fit.ellipse.size.width, fit.ellipse.size.height);
    const double semiMinor = 0.5 * std::min(fit.ellipse.size.width, fit.ellipse.size.height);
    const double ratio =
        std::max(kRoundest, ctx.priors.eyeRatio > 0.0 ? ctx.priors.eyeRatio - kEyeMargin : 0.0);
    if (semiMinor >= ratio * semiMajor) {
        return std::nullopt;
    }
    std::vector<cv::Point2d> points, gradients;
    for (std::size_t i = 0; i < ctx.points.size(); ++i) {
        if (ctx.gradients[i].y >= kFacingUp) {
            points.push_back(ctx.points[i]);
            gradients.push_back(ctx.gradients[i]);
        }
    }
    if (points.size() < 12) {
        return std::nullopt;
    }
    RansacEllipseParams rounder = rp;
    rounder.minAxisRatio = ratio;
    rounder.minAxis = 2.0 * std::max(0.5 * semiMajor, 1.1 * semiMinor);
    rounder.maxAxis = 2.0 * kWider * semiMajor;
    rounder.seed += 13;
    // Half the draws: the refit runs for every flat candidate, most of them no pupil under a lid,
    // and fails after all its draws when no round ellipse explains them; half find as many.
    rounder.iterations = std::max(20, rp.iterations / 2);
    auto refit = fitEllipseRansac(points, rounder, gradients);
    // It must move towards the lid over the top.
    if (!refit || refit->ellipse.center.y >= fit.ellipse.center.y ||
        !addsOnlyLid(ctx, *refit, fit, kKeptInliers)) {
        return std::nullopt;
    }
    return refit;
}

// What the refits before it cannot place: an arc too short to fix an ellipse's five parameters,
// where no lid line, learnt size or limbus gives the missing one, lets the fit flatten against
// the lid with its centre low. Where the pupil is seen decides its shape (pupil_shape_model.hpp),
// so once the eye's whole pupils have taught that, only the centre and the size are left to fit
// (fitEllipseOfShapeRansac): a fit whose ratio is off the prediction by more than the model's
// scatter, or whose axis is turned away from it, is refitted that way. The refit must keep most
// of the inliers and the visible outline's support: a pupil that has not the shape the model
// expects (a model learnt from few directions, refraction) keeps its own fit, as its points do
// not lie on the other.
std::optional<EllipseFit> fitToEyeShape(const RefitContext& ctx, const EllipseFit& fit) {
    const cv::Mat& grey = ctx.grey;
    const RayLevels& lv = ctx.levels;
    const RansacEllipseParams& rp = ctx.ransac;
    constexpr double kRatioBand = 0.08;  // axis ratio off the prediction by more: refitted
    constexpr double kAngleBand = 20.0;  // major axis turned from the predicted by more, deg
    constexpr double kRound = 0.92;      // both rounder: the axis's direction means nothing
    constexpr double kKeptInliers = 0.6; // of the fit's
    constexpr double kSupportMargin = 0.1;
    constexpr int kDraws = 60;
    constexpr double kSameRatio = 0.01; // a shape this close to the first needs no second refit
    constexpr double kSameAngle = 2.0;  // deg
    const cv::RotatedRect& e = fit.ellipse;
    const auto shape = ctx.priors.shape.predict({e.center.x, e.center.y});
    if (!shape) {
        return std::nullopt;
    }
    const PupilShape own = shapeOf(e);
    const bool round = shape->axisRatio > kRound && own.axisRatio > kRound;
    if (std::abs(own.axisRatio - shape->axisRatio) < kRatioBand &&
        (round || axisTurnDeg(own.majorAngleDeg, shape->majorAngleDeg) < kAngleBand)) {
        return std::nullopt;
    }
    RansacEllipseParams shaped = rp;
    shaped.seed += 19;
    // A draw of three points is all inliers far more often than one of five: 60 draws find as
    // many pupils as 150.
    shaped.iterations = kDraws;
    auto refit = fitEllipseOfShapeRansac(ctx.points, shape->axisRatio, shape->majorAngleDeg, shaped,
                                         ctx.gradients);
    if (!refit) {
        return std::nullopt;
    }
    // The shape where the refit is, once more, when it differs there.
    const auto there = ctx.priors.shape.predict({refit->ellipse.center.x, refit->ellipse.center.y});
    if (there && (std::abs(there->axisRatio - shape->axisRatio) > kSameRatio ||
                  axisTurnDeg(there->majorAngleDeg, shape->majorAngleDeg) > kSameAngle)) {
        if (auto again = fitEllipseOfShapeRansac(ctx.points, there->axisRatio, there->majorAngleDeg,
                                                 shaped, ctx.gradients)) {
            refit = again;
        }
    }
    if (static_cast<double>(refit->inliers.size()) <
            kKeptInliers * static_cast<double>(fit.inliers.size()) ||
        outlineSupport(grey, refit->ellipse, lv).visible <
            outlineSupport(grey, e, lv).visible - kSupportMargin) {
        return std::nullopt;
    }
    return refit;
}

// A pupil under the upper lid whose visible arc leaves its height open (the refits before it need
// a size learnt from the whole pupil, or a lid whose edges face up, and on some eyes have
// neither): the iris around it fixes it (limbus_fit.hpp). A fit flatter than 0.85 is refitted;
// the concentric fit is taken when most of the visible arc's points and half the limbus points
// lie on it, the limbus points span 100 deg or more (bunched on one side they leave the shape
// open), it moves the centre up (towards the lid), makes the pupil rounder by 0.1 or more (a
// smaller change is within the noise of the limbus's own shape, and would move right answers on
// eyes seen from a steep angle) and adds nothing darker than the iris (below). The limbus alone
// is not enough: its own arc is cut by the same lid.
std::optional<EllipseFit> fitWithLimbus(const RefitContext& ctx, const EllipseFit& fit) {
    const cv::Mat& grey = ctx.grey;
    const RayLevels& lv = ctx.levels;
    constexpr double kFlat = 0.85;         // fits flatter than this are refitted
    constexpr double kKeptPupil = 0.6;     // of the arc's points, on the concentric fit
    constexpr double kKeptLimbus = 0.5;    // of the limbus points, on it
    constexpr int kLeastPoints = 8;        // on each ellipse
    constexpr double kLeastSpread = 100.0; // deg spanned by the limbus points on the fit
    constexpr double kRounder = 0.1;       // the least gain in axis ratio
    constexpr double kLeastRatio = 0.6;    // the concentric fit's least axis ratio
    // Fits whose visible outline is less supported seldom win, and the limbus search and the
    // concentric fit cost a tenth of the detector's time when run on every flat fit.
    constexpr double kLeastSupport = 0.6;
    const cv::RotatedRect& e = fit.ellipse;
    const double major = 0.5 * std::max(e.size.width, e.size.height);
    const double minor = 0.5 * std::min(e.size.width, e.size.height);
    if (minor >= kFlat * major) {
        return std::nullopt;
    }
    if (outlineSupport(grey, e, lv).visible < kLeastSupport) {
        return std::nullopt;
    }
    const std::vector<cv::Point2d> arc = visibleArc(ctx, e);
    if (arc.size() < static_cast<std::size_t>(kLeastPoints)) {
        return std::nullopt;
    }
    LimbusSearch search;
    search.irisLevel = lv.surround;
    search.glintLevel = lv.glint;
    std::vector<cv::Point2d> limbus;
    findLimbusPoints(ctx.smooth, e, search, limbus);
    if (limbus.size() < static_cast<std::size_t>(kLeastPoints)) {
        return std::nullopt;
    }
    const auto placed = fitConcentric(arc, limbus, e, kLeastRatio);
    if (!placed || placed->pupilInliers < std::max<double>(kLeastPoints, kKeptPupil * arc.size()) ||
        placed->limbusInliers < std::max<double>(kLeastPoints, kKeptLimbus * limbus.size()) ||
        placed->limbusSpreadDeg < kLeastSpread) {
        return std::nullopt;
    }
    const cv::RotatedRect& p = placed->pupil;
    const double ratio = std::min(p.size.width, p.size.height) /
                         std::max(1e-6F, std::max(p.size.width, p.size.height));
    if (p.center.y >= e.center.y - 0.5 || ratio - minor / major < kRounder) {
        return std::nullopt;
    }
    // What it adds must be no darker than the iris next to the pupil: a whole pupil seen from a
    // steep angle is flat too, and a limbus found a little rounder than it would lift its top
    // into the iris. Not addsOnlyLid's test (brighter than the iris by a quarter of the pupil's
    // contrast): lashes along the lid darken what a pupil under it adds.
    if (medianBeyond(grey, p, e, lv.glint) < lv.surround) {
        return std::nullopt;
    }
    EllipseFit out;
    out.ellipse = p;
    return out;
}

} // namespace gt::eyetrack::starburst
