#pragma once
// Stage 4 of the starburst detector: how much a fitted ellipse looks like the pupil.
//
// After PuRe's outline contrast (Santini, Fuhl & Kasneci 2018): the share of points along the
// fitted ellipse where the image is clearly darker just inside than just outside, on its visible
// part times the whole outline's to the power 1/4. An eyelid or lashes covering part of the
// outline lower it, less than in proportion; a blink (no dark outline at all) drives it to ~0.
// Edge sharpness (a pupil's edge is optics-sharp, a shadow's ramp is not), a filled dark inside
// and a shape the camera can see a pupil at scale it. Size consistency with the recent pupil
// (PuReST, Santini, Fuhl & Kasneci 2018) is applied by the detector, which knows the recent size.
// The probability that the detector's answer is right is answer_confidence.hpp's.
#include <opencv2/core.hpp>

#include "pupil/edge_rays.hpp"

namespace gt::eyetrack::starburst {

// Share of the fitted outline with a dark inside and a brighter outside: `all` counts every
// sample (the reported confidence, which falls under occlusion); `visible` leaves out the
// samples where the outline runs through something bright on both sides (an eyelid over the
// pupil), so candidates are compared on what can be seen: an ellipse shrunk to hug the lid's
// edge otherwise outscores the true, partly covered pupil.
struct OutlineSupport {
    double all = 0.0, visible = 0.0;
    double sharpness = 0.0; // median edge step ratio, 1 = a crisp edge
};
[[nodiscard]] OutlineSupport outlineSupport(const cv::Mat& grey, const cv::RotatedRect& e,
                                            const RayLevels& lv);

// Median grey level a few pixels outside the ellipse, glints excluded (the iris next to a pupil);
// -1 when too little of the ring is on the image.
[[nodiscard]] double outsideLevel(const cv::Mat& grey, const cv::RotatedRect& e,
                                  const RayLevels& lv);

// Share of the ellipse's inner area darker than the threshold (glints aside), its median and
// upper quartile.
struct Interior {
    double fill = 0.0, median = 255.0, upperQuartile = 255.0;
};
[[nodiscard]] Interior interiorFill(const cv::Mat& grey, const cv::RotatedRect& e,
                                    const RayLevels& lv);

// Median grey level of the part of ellipse e's inside that lies outside `inner` (glints left
// out): what a larger refit adds to a smaller one; -1 when fewer than 4 samples fall there.
[[nodiscard]] double medianBeyond(const cv::Mat& grey, const cv::RotatedRect& e,
                                  const cv::RotatedRect& inner, double glint);

// Size consistency (PuReST): 1 for the recent pupil's size (or none known, recentRadius 0),
// falling as a Gaussian in the log of the size ratio.
[[nodiscard]] double sizeConsistency(double semiMajor, double recentRadius);

// The round end of the axis-ratio ramp: `configured`, or moved down to eyeRatioMargin below the
// axis ratio this eye's whole pupil has shown (eyeRatio > 0), never within 0.1 of `flattest`.
[[nodiscard]] double roundAxisRatio(double configured, double flattest, double eyeRatioMargin,
                                    double eyeRatio);

// What the detector measured on a fitted ellipse.
struct FitEvidence {
    double confidence = 0.0;     // the detector's own, before the size prior
    double visibleSupport = 0.0; // OutlineSupport::visible
    double supportAll = 0.0;     // the whole outline's support (1: nothing covers it)
    double quality = 0.0;        // sharpness x filled interior: how much it looks like a pupil
    double interior = 0.0;       // median grey level inside
    double interiorHigh = 0.0;   // its upper quartile (the iris, when a pupil sits inside)
    double outside = -1.0;       // median grey level just outside the outline (-1: unknown)
    double shapeFactor = 1.0;    // the axis-ratio ramp's factor in the confidence
    double fill = 0.0;           // share of dark samples inside (interiorFill)
    double axisRatio = 0.0;      // minor over major axis of the fit
};

// The evidence for ellipse e, its shape judged on a ramp from 0 at axis ratio `flattest` to 1 at
// `round` (StarburstConfig::flattestAxisRatio, roundAxisRatio()).
[[nodiscard]] FitEvidence judgeFit(const cv::Mat& grey, const cv::RotatedRect& e,
                                   const RayLevels& lv, double flattest, double round);

} // namespace gt::eyetrack::starburst
