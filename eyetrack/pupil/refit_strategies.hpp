#pragma once
// Stage 3b of the starburst detector: refits of an ellipse the lid or lashes left open.
//
// The RANSAC fit (ellipse_fit.hpp) follows the edge points; where the pupil is partly covered,
// points along a lid's margin or lashes pull it flat, low or large. Each strategy here refits the
// same edge points with one more thing that is known: a lid line, the recent pupil size, the
// upper lid's edge direction, the shape the eye's whole pupils have shown at that place
// (pupil_shape_model.hpp, after Świrski & Dodgson 2013) and the limbus around the pupil
// (limbus_fit.hpp). The detector walks refitStrategies() in order; each strategy returns a refit
// only when it is clearly better than what it was given, and the next starts from the result.
#include <optional>
#include <span>
#include <string_view>

#include <opencv2/core.hpp>

#include "pupil/edge_rays.hpp"
#include "pupil/ellipse_fit.hpp"
#include "pupil/pupil_priors.hpp"

namespace gt::eyetrack::starburst {

// What a refit may use besides the fit it is given.
struct RefitContext {
    const cv::Mat& grey;                    // the frame (outline support, what a refit adds)
    const cv::Mat& smooth;                  // its 3x3 box mean (the limbus search)
    std::span<const cv::Point2d> points;    // the second ray pass's edge points
    std::span<const cv::Point2d> gradients; // their unit gradients, dark -> bright
    const RayLevels& levels;
    const RansacEllipseParams& ransac; // the second pass's fit's parameters
    const PupilPriors& priors;
};

using Refit = std::optional<EllipseFit> (*)(const RefitContext&, const EllipseFit&);

struct RefitStrategy {
    std::string_view name;
    Refit refit;
    // Strategies with the same nonzero `alternatives` are alternatives to one another: once one
    // of them refits, the rest of that group are skipped.
    int alternatives = 0;
    // Holds the fit to the recent pupil size. The confidence's size factor is judged on the fit
    // from before the first such strategy, so a fit held to the prior is not made surer by it.
    bool heldToRecentSize = false;
};

// The strategies in the order the detector applies them: "lid line", then the first that
// refits of "recent size", "under lid" and "rounder under lid", then "eye shape", then "limbus".
[[nodiscard]] std::span<const RefitStrategy> refitStrategies();

struct Refitted {
    EllipseFit fit;
    double fittedSemiMajor = 0.0; // before the first refit held to the recent size
};
// `fit` after every strategy of `strategies` (refitStrategies() by default), in order.
[[nodiscard]] Refitted applyRefits(const RefitContext& ctx, EllipseFit fit);
[[nodiscard]] Refitted applyRefits(const RefitContext& ctx, EllipseFit fit,
                                   std::span<const RefitStrategy> strategies);

// The strategies one by one (tests call them directly); each returns nullopt when it does not
// apply or its refit is not clearly better.
// A refit without the edge points along a lid over the pupil (a long straight run across the
// image, off the centre), when the new ellipse reaches beyond the lid.
[[nodiscard]] std::optional<EllipseFit> fitBesideLid(const RefitContext& ctx,
                                                     const EllipseFit& fit);
// A refit within the recent pupil size when `fit` is clearly larger and the smaller fit explains
// the points about as well.
[[nodiscard]] std::optional<EllipseFit> fitAtRecentSize(const RefitContext& ctx,
                                                        const EllipseFit& fit);
// A refit at least nearly as wide as the recent pupil when `fit` is much narrower (its outline
// hugging a lid over the pupil) and what the wider ellipse adds lies under something brighter
// than the iris.
[[nodiscard]] std::optional<EllipseFit> fitUnderLid(const RefitContext& ctx, const EllipseFit& fit);
// Without a recent pupil to go by: a refit of the edge points that do not face up (a lid over
// the pupil's top gives edges facing up), at least as round as the pupils a head-mounted camera
// sees, when `fit` is flatter and what the rounder ellipse adds lies under something brighter
// than the iris.
[[nodiscard]] std::optional<EllipseFit> fitRounderUnderLid(const RefitContext& ctx,
                                                           const EllipseFit& fit);
// A refit held to the shape the eye's pupils have at that place when `fit`'s shape is well off
// it, the refit keeps most of its inliers and its visible outline is about as well supported.
[[nodiscard]] std::optional<EllipseFit> fitToEyeShape(const RefitContext& ctx,
                                                      const EllipseFit& fit);
// A pupil under the lid placed by its iris: the visible arc of a flat fit and the limbus below
// it fitted as two concentric ellipses of one shape, when that makes the pupil clearly rounder
// and moves it up. It has no inliers (the arc's points are not ctx.points'; nothing after it
// reads them).
[[nodiscard]] std::optional<EllipseFit> fitWithLimbus(const RefitContext& ctx,
                                                      const EllipseFit& fit);

} // namespace gt::eyetrack::starburst
