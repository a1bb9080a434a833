#pragma once
// The pupil under a lid, placed by its iris: the pupil and the iris are concentric discs on one
// plane (the pupil's offset from the iris centre is a few tenths of a millimetre), so the camera
// sees two concentric ellipses of the same shape and angle. A lid over the pupil's top hides
// the part of its outline that fixes its height; the two lower arcs do not: each gives its
// ellipse's lowest point and width, and two concentric ellipses of one shape through both fix
// the shape and the centre (the widths differ by the iris's rim, so the ratio is well
// conditioned). Points on the limbus (iris -> sclera) are found along rays below the pupil.
#include <optional>
#include <span>
#include <vector>

#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

namespace gt::eyetrack {

struct LimbusSearch {
    double irisLevel = 0.0;    // grey level of the iris next to the pupil
    double glintLevel = 255.0; // at or above: a glint, not the sclera
    double minStep = 35.0;     // the sclera is at least this much brighter than the iris
    double maxReach = 7.0;     // furthest limbus, in pupil semi-major axes from the centre
    int rays = 32;
};

// Limbus edge points along rays from the pupil's centre that do not point up (the upper lid
// covers the limbus's top first): on each, the first rise from the iris (its level on that ray
// just outside the pupil, or irisLevel if darker) to a plateau clearly brighter (the sclera),
// at the half-way level between the darkest point before it (the limbal ring) and the plateau.
void findLimbusPoints(const cv::Mat& smooth, const cv::RotatedRect& pupil, const LimbusSearch& s,
                      std::vector<cv::Point2d>& points);

struct ConcentricFit {
    cv::RotatedRect pupil, limbus;
    int pupilInliers = 0, limbusInliers = 0;
    double limbusSpreadDeg = 0.0; // angle spanned by the limbus inliers around the centre
};

// Two concentric ellipses of one shape (centre, pupil semi-major a, axis ratio r >= minRatio,
// angle, limbus scale k) through the pupil's and the limbus's points, by Levenberg-Marquardt
// on radial distances with Cauchy weights (scale 1.5 px), from `start` (the pupil's fit).
[[nodiscard]] std::optional<ConcentricFit> fitConcentric(std::span<const cv::Point2d> pupilPoints,
                                                         std::span<const cv::Point2d> limbusPoints,
                                                         const cv::RotatedRect& start,
                                                         double minRatio);

} // namespace gt::eyetrack
