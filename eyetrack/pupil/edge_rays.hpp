#pragma once
// Stage 2 of the starburst detector: edge points on the pupil's outline.
//
// Starburst (Li, Winfield & Parkhurst 2005): from a candidate, rays are cast outwards; on each,
// the first dark-to-bright crossing of a threshold between the pupil's and the iris's grey
// levels gives a sub-pixel boundary point (at the half-way level, a symmetric blur leaves the
// edge position unbiased). A ray whose crossing touches a saturated glint is dropped (glint
// suppression), so glints on the boundary do not bend it, and so is one whose outside is not
// the iris (skin beyond a lid margin, sclera beyond a dark iris).
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "pupil/bilinear.hpp"
#include "pupil/candidate_search.hpp"

namespace gt::eyetrack::starburst {

// An edge whose outside lies more than this share of the pupil-iris contrast above the iris
// level opens onto skin (a lid over the pupil), not the iris: the lower margin of a lid covering
// the pupil's top is about 0.4 of the contrast above the iris, and a fit along it puts the centre
// several pixels low, confidently, as the edge is crisp.
inline constexpr double kSkinAboveIris = 0.25;

// The grey levels a ray walk goes by.
struct RayLevels {
    double pupil = 0.0, surround = 0.0, threshold = 0.0, glint = 255.0;
};

// The sensor noise's standard deviation (grey levels) of `grey`, `smooth` its 3x3 box mean.
[[nodiscard]] double noiseSigma(const cv::Mat& grey, const cv::Mat& smooth);

// The pupil's and its surround's levels around a candidate, the first walk's threshold between
// them (clear of the frame's `noise`) and the glint level; nullopt when the two are less than
// minContrast apart (no pupil there).
[[nodiscard]] std::optional<RayLevels> measureLevels(const cv::Mat& grey, const Candidate& c,
                                                     double minContrast, double noise);

// Whether p is on a glint: saturated, or a small spot much brighter than its 9x9 neighbourhood
// (its mean read off `fullIntegral`, the raw frame's CV_32S integral image).
[[nodiscard]] bool isGlint(const cv::Mat& grey, const cv::Mat& fullIntegral, cv::Point2d p,
                           const RayLevels& lv);

// What the rays walk: the 3x3-smoothed frame, its BilinearRange (which answers most of the
// walk's threshold tests) and the raw frame's integral image (for the glint test).
struct RayImage {
    const cv::Mat& smooth;
    const BilinearRange& cells;
    const cv::Mat& fullIntegral;
};

class EdgeRays {
public:
    // `rays` evenly spaced directions, set once (not a sincos per ray per cast).
    explicit EdgeRays(int rays);

    // Casts every stride-th ray from `from` out to maxDistance and keeps each ray's boundary
    // point. irisOnly (the second pass, the iris level measured around a first fit): only edges
    // that open onto the iris count.
    void cast(const RayImage& image, cv::Point2d from, double maxDistance, const RayLevels& lv,
              bool irisOnly = false, int stride = 1);

    [[nodiscard]] const std::vector<cv::Point2d>& points() const noexcept { return mPoints; }
    // Unit image gradients at the points, dark -> bright; zero where flat.
    [[nodiscard]] const std::vector<cv::Point2d>& gradients() const noexcept { return mGradients; }

private:
    void walk(const RayImage& image, cv::Point2d from, cv::Point2d dir, double maxDistance,
              const RayLevels& lv, bool irisOnly);
    // The crossing at t (sample v, prev the level before it) is the ray's edge: kept unless a
    // glint is on it or what lies beyond is not the iris.
    void keepEdge(const RayImage& image, cv::Point2d from, cv::Point2d dir, double t, double prev,
                  double v, const RayLevels& lv, bool irisOnly);

    std::vector<cv::Point2d> mDirections; // unit, one per ray
    std::vector<cv::Point2d> mPoints;
    std::vector<cv::Point2d> mGradients;
};

} // namespace gt::eyetrack::starburst
