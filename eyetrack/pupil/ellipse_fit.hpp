#pragma once
// Outlier-robust ellipse fitting for pupil edge points.
//
// RANSAC (Fischler & Bolles 1981) over minimal 5-point conics, scored by inlier count under the
// Sampson distance (first-order geometric distance |Q(p)| / |grad Q(p)|), then a least-squares
// refit on the consensus set with the direct ellipse fit (Fitzgibbon et al. 1999, which can only
// return ellipses). Świrski et al. 2012 use the same idea for pupils; edges from eyelids,
// lashes and glints are the outliers it removes. Like Świrski's, an inlier must also agree in
// direction: its image gradient (dark pupil -> bright surround) must point along the ellipse's
// outward normal, so edge points of an eyelid or lash that happen to lie near a candidate curve
// (their gradient points across the lid, not away from the pupil) do not vote for it. The test
// costs nothing measurable: the distance check is done without a square root.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <opencv2/core/types.hpp>

namespace gt::eyetrack {

// General conic a x^2 + b xy + c y^2 + d x + e y + f = 0.
struct Conic {
    double a = 0, b = 0, c = 0, d = 0, e = 0, f = 0;

    [[nodiscard]] double value(cv::Point2d p) const {
        return a * p.x * p.x + b * p.x * p.y + c * p.y * p.y + d * p.x + e * p.y + f;
    }
    // First-order geometric distance from p to the curve.
    [[nodiscard]] double sampsonDistance(cv::Point2d p) const;
    [[nodiscard]] cv::Point2d gradient(cv::Point2d p) const {
        return {2.0 * a * p.x + b * p.y + d, b * p.x + 2.0 * c * p.y + e};
    }
    [[nodiscard]] bool isEllipse() const { return b * b - 4.0 * a * c < 0.0; }
    // Centre, full axes and angle (OpenCV's RotatedRect convention); nullopt if not an ellipse.
    [[nodiscard]] std::optional<cv::RotatedRect> toEllipse() const;
    [[nodiscard]] static Conic fromEllipse(const cv::RotatedRect& e);
};

// The conic through five points (nullopt when they are degenerate).
[[nodiscard]] std::optional<Conic> conicThrough(std::span<const cv::Point2d, 5> p);

// The least-squares ellipse through points[i] for i in `subset` (all points when empty): the
// direct fit of Fitzgibbon, Pilu and Fisher 1999 (minimise the algebraic distance subject to
// 4ac - b^2 = 1, so the answer is always an ellipse), solved in the numerically stable form of
// Halir and Flusser 1998 (a 3x3 eigenproblem on centred, scaled coordinates). nullopt for fewer
// than six points or a degenerate set (all on a line or a conic that is no ellipse).
[[nodiscard]] std::optional<Conic> directEllipseFit(std::span<const cv::Point2d> points,
                                                    std::span<const int> subset = {});

struct RansacEllipseParams {
    int iterations = 80; // at most
    // Adaptive stop (Fischler & Bolles 1981; Hartley & Zisserman §4.7): after at least
    // minIterations, stop once an all-inlier sample would have been drawn with this probability
    // had the inlier share been the best one found so far. 0 or 1 = always run `iterations`.
    int minIterations = 30;
    double stopConfidence = 0.9999;
    double inlierDistance = 1.0; // pixels
    double minAxis = 2.0;        // full axis length bounds, pixels
    double maxAxis = 1e9;
    double minAxisRatio = 0.4; // minor / major (a pupil seen 66 deg off-axis)
    double minNormalCos = 0.8; // edge gradient vs outward normal: at most ~37 deg apart
    std::uint64_t seed = 1;
};

struct EllipseFit {
    cv::RotatedRect ellipse;
    std::vector<int> inliers; // indices into the points
    int draws = 0;            // RANSAC samples drawn before it stopped
};

// Draws after which an all-inlier sample of `sampleSize` points (5 for a conic, 3 for a circle)
// has been made with probability `confidence` when a share `inlierShare` of the points are
// inliers (0 when all are), at most `cap`.
[[nodiscard]] int ransacDrawsNeeded(double inlierShare, double confidence, int cap,
                                    int sampleSize = 5);

// `gradients`, when given, holds each point's unit image gradient (pointing from dark to bright;
// a zero vector when unknown), and inliers must agree with the ellipse's outward normal.
[[nodiscard]] std::optional<EllipseFit>
fitEllipseRansac(std::span<const cv::Point2d> points, const RansacEllipseParams& params,
                 std::span<const cv::Point2d> gradients = {});

// The same RANSAC with the ellipse's shape given (axis ratio minor / major and the major axis's
// direction, degrees): only its centre and size are free, so three points fix it. In the frame
// where that shape is a circle (rotated onto the major axis, the minor direction stretched by
// 1 / ratio) each draw is the circle through three points and the refit a least-squares circle
// (Kåsa 1976) on the inliers, two rounds as above; inliers are judged in the image as above.
// An arc too short to fix five parameters — a pupil half under the lid — fixes three.
[[nodiscard]] std::optional<EllipseFit>
fitEllipseOfShapeRansac(std::span<const cv::Point2d> points, double axisRatio, double majorAngleDeg,
                        const RansacEllipseParams& params,
                        std::span<const cv::Point2d> gradients = {});

} // namespace gt::eyetrack
