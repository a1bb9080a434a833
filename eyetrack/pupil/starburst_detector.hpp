#pragma once
// The default pupil detector (`--detector starburst`) for near-infrared eye images.
//
// Method (our own code; the ideas are from the published detectors):
//  1. Coarse search (Świrski, Bulling & Dodgson 2012): on a downscaled image's integral image, a
//     centre-surround box feature (mean of a surrounding ring minus mean of an inner box) over a
//     range of radii finds dark compact regions; the strongest local maxima of each radius,
//     after non-maximum suppression across radii, are candidates. Cost O(1) per position and
//     radius. The same search runs inside the winner, inside the best blob by its own evidence
//     and inside an iris-sized candidate that yields no fit, for a pupil in a dark iris. When
//     no candidate is confident, the next strongest blobs are tried as well.
//  2. Edge points (Starburst, Li, Winfield & Parkhurst 2005): from each candidate, rays are cast
//     outwards; on each, the first dark-to-bright crossing of a threshold halfway between the
//     pupil's and the iris's grey levels gives a sub-pixel boundary point (at the half-way level,
//     a symmetric blur leaves the edge position unbiased). A ray whose crossing touches a
//     saturated glint is dropped (glint suppression), so glints on the boundary do not bend it.
//  3. Ellipse: RANSAC over 5-point conics, refit on the inliers (pupil/ellipse_fit.hpp), then the
//     rays are recast from the fitted centre and the fit repeated, which evens out the points
//     when the candidate was off-centre. Candidates whose first fit repeats an earlier one's
//     stop there. A fit the lid or lashes left open is refitted with what else is known: a lid
//     line, the recent size, the limbus, and the shape the eye's whole pupils have shown at that
//     place (pupil_shape_model.hpp, after Świrski & Dodgson 2013).
//  4. Confidence (after PuRe's outline contrast, Santini, Fuhl & Kasneci 2018): the share of
//     points along the fitted ellipse where the image is clearly darker just inside than just
//     outside, on its visible part times the whole outline's to the power 1/4. An eyelid or
//     lashes covering part of the outline lower it, less than in proportion; a blink (no dark
//     outline at all) drives it to ~0. Edge sharpness (a pupil's edge is optics-sharp, a
//     shadow's ramp is not) and a filled dark inside scale it, and so does size consistency with
//     the recent pupil (PuReST, Santini, Fuhl & Kasneci 2018), so a lash gap in a blink scores
//     low. The candidate with the best confidence wins, with a preference for last frame's
//     pupil.
// Output: sub-pixel centre, ellipse and confidence. Pixel centres are at integer coordinates.
#include <cstdint>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "pupil/answer_confidence.hpp"
#include "pupil/bilinear.hpp"
#include "pupil/ellipse_fit.hpp"
#include "pupil/pupil_detector.hpp"
#include "pupil/pupil_shape_model.hpp"

namespace gt::eyetrack {

struct StarburstConfig {
    // Pupil radius bounds in pixels; 0 = from the image's shorter side (3 % .. 25 %).
    double minRadius = 0.0;
    double maxRadius = 0.0;
    // Rays cast from each candidate's fitted centre (the second pass). More rays put more edge
    // points between lashes crossing the pupil's top and between glints on its border, so
    // RANSAC finds the outline's consensus more often; tracking (below) left the time for them.
    // eyescore, 64 -> 128 rays (the first pass at 64; the confidence refitted for each, and the
    // test on what rings a darker blob inside the winner, detect()): on 600 fresh wild seeds
    // never used before (30001-30300, 40001-40300) 95.88 -> 96.15 % within 5 px, ROC area 0.9907
    // both, the gaze filter's gate (0.7 -> 0.75) rejecting 92.59 -> 92.75 % of the wrong answers
    // and keeping 96.95 -> 96.84 % of the right ones, eleven of the twelve 50-seed sets meeting
    // 90 % / 95 % (nine before); wild development seeds 1-150 / 151-300 97.19 / 96.03 -> 97.29
    // / 96.15 %; hard 1-100 / 101-200 99.84 / 99.88 -> 99.89 / 99.90 %. bench --suite eye, hard,
    // alternated: 1,475-1,622 -> 1,192-1,433 fps. Both passes at 128: 96.27 % on the fresh
    // seeds but 987-1,102 fps; 192 rays 96.20 %; eight more fallback and seven first-round blobs
    // instead of more rays 95.83 %.
    int rays = 128;
    // The first pass, from the blob's centre, casts this many of them (a divisor of `rays`):
    // its fit only places the second pass's centre and levels, and most blobs end there.
    int seedRays = 64;
    int candidates = 5;
    // When no candidate of the first round reaches `fallbackBelow` confidence (the level at
    // which a pupil is also next frame's prior), up to `fallbackCandidates` further blobs are
    // refined too, their confidence scaled by `fallbackConfidence`: shadows and lash clusters
    // darker than the pupil can fill the first round, but more tries in frames where the pupil
    // may be hidden also give a speck or a lash loop more chances to look like one (unscaled,
    // the gaze filter's gate let 1.4 points more wrong answers through on wild development
    // seeds). Eight blobs of the closed image (below) instead of five, eyescore, development
    // seeds, wild 1-150 / 151-300: 96.32 / 95.28 -> 96.51 / 95.33 % within 5 px, gate 0.6
    // rejecting 91.4 / 92.4 -> 91.1 / 92.3 % of wrong answers and keeping 96.4 / 95.1 -> 96.4 /
    // 95.0 % of right ones; hard 1-100 / 101-200 99.76 / 99.80 -> 99.75 / 99.80 %, 2 % more
    // instructions per frame (callgrind, hard seed 5). Ten: 96.58 / 95.48 %, but answers with
    // the detector's own confidence in 9 of the 41 blink frames of PupilDetector's hard clip
    // (five: 3, eight: 6; the test allows a fifth).
    int fallbackCandidates = 8;
    double fallbackBelow = 0.6;
    double fallbackConfidence = 0.8;
    // The fallback round's blobs come from the image closed (a grey-level closing: dark
    // structures narrower than the square removed) with a square of about `fallbackClosing`
    // times the least pupil radius on a side (13 px at 320 x 240): lashes crossing or crowding
    // a pupil merge with it into one irregular blob that ranks below lash clusters and shadows,
    // and without them the pupil is a round blob again. 0 = the plain search's next blobs.
    double fallbackClosing = 1.8;
    int ransacIterations = 150;
    double inlierDistance = 1.0; // pixels
    double minContrast = 12.0;   // grey levels between pupil and surround
    double minConfidence = 0.35; // below: no pupil reported
    // Plausible pupil shapes for the camera (the "plausible eccentricity"), as the ratio
    // of the fitted ellipse's minor to major axis: the confidence is scaled by a smooth ramp
    // from 0 at `flattestAxisRatio` to 1 at `roundAxisRatio`. A pupil seen within ~37 deg of
    // the camera's axis (cos 37 deg = 0.8) keeps its confidence, at 45 deg 0.91 of it, at 50 deg
    // 0.77, at 60 deg 0.35; the sliver of a pupil mostly under the lid is fitted at 0.4-0.6. Lower
    // both for a camera set further off the eye's axis than a head-mounted one.
    double flattestAxisRatio = 0.3;
    double roundAxisRatio = 0.8;
    // The ramp's round end follows the eye: it moves down to `eyeRatioMargin` below the axis
    // ratio this eye's pupil has shown whole (learnt from confident fits whose outline is seen
    // all round), so the pupils of an eye the camera sees from a steep angle, flat wherever they
    // look, keep their confidence; slivers under the lid of an eye seen head-on do not gain any.
    // 0 = the fixed ramp.
    double eyeRatioMargin = 0.1;
    // Tracking: when last frame's pupil, refined first, is found again within half its
    // semi-major axis (5 px at least) with at least `trackingConfidence` (the detector's own,
    // the size prior applied), `trackingSupport` of its visible outline supported and a
    // uniformly dark inside, the frame's other blobs are not refined. eyescore, development
    // seeds, against refining every blob: wild 1-150 / 151-300 97.17 / 96.04 -> 97.19 / 96.03 %
    // within 5 px, ROC area 0.9932 / 0.9923 -> 0.9933 / 0.9923, gate 0.7 rejecting 94.56 / 94.86
    // -> 94.61 / 94.81 % of wrong answers and keeping 97.55 / 96.71 -> 97.55 / 96.69 % of right
    // ones; hard 1-100 / 101-200 99.84 / 99.88 -> 99.84 / 99.88 % (rejecting 98.49 / 98.26 ->
    // 98.38 / 98.20 %, keeping 99.92 / 99.90 -> 99.92 / 99.89 %); callgrind, hard seed 5, 300
    // frames: 6.89 M -> 4.23 M instructions a frame. At 0.8: wild 97.18 / 95.95 %, the gate
    // rejecting 94.55 / 94.47 %. 0 = always search.
    double trackingConfidence = 0.9;
    double trackingSupport = 0.9;
};

class StarburstDetector final : public PupilDetector {
public:
    explicit StarburstDetector(StarburstConfig config = {});

    // grey: CV_8UC1 (any size; throws EyetrackError otherwise). Frames are expected in order:
    // the last result is a prior for the next (reset() forgets it, e.g. between videos).
    [[nodiscard]] PupilResult detect(const cv::Mat& grey, double tMs) override;
    using PupilDetector::detect;

    void reset() override {
        mLast = {};
        mEvidence = {};
        mRecentRadius = 0.0;
        mRecentMinor = 0.0;
        mRecentLevel = -1.0;
        mRecentContrast = 0.0;
        mEyeRatio = 0.0;
        mShape.reset();
    }
    [[nodiscard]] std::string name() const override { return "starburst"; }
    // How many blobs the last detect() refined (cast rays from and fitted): 1 in a frame where
    // tracking last frame's pupil sufficed, the work a frame took otherwise.
    [[nodiscard]] int blobsRefined() const { return mBlobsRefined; }
    [[nodiscard]] const StarburstConfig& config() const noexcept { return mConfig; }
    // What the last detect() measured on its answer, from which it reported the confidence
    // (eyescore --answers writes it, to refit answerProbability).
    [[nodiscard]] const AnswerEvidence& lastEvidence() const noexcept { return mEvidence; }

private:
    struct Candidate {
        cv::Point2d centre;
        double radius = 0.0;
        double response = 0.0;
    };
    struct Levels {
        double pupil = 0.0, surround = 0.0, threshold = 0.0, glint = 255.0;
    };

    // The strongest dark blobs of the image behind `fullIntegral` (the size of `grey`), each
    // unlike those already in `out`, appended until `out` holds `limit`; `small` and `integral`
    // receive the coarse image searched and its integral.
    void findCandidates(const cv::Mat& grey, const cv::Mat& fullIntegral, double minR, double maxR,
                        cv::Mat& small, cv::Mat& integral, std::vector<Candidate>& out,
                        std::size_t limit);
    // The fallback round's blobs in place of mCandidates' after its first `firstRound`.
    void findFallbackCandidates(const cv::Mat& grey, double minR, double maxR,
                                std::size_t firstRound);
    // The strongest smaller dark blob within an outer blob (its centre and minor semi-axis, and
    // outerInterior: the level around a pupil in it); coarse image, after findCandidates.
    [[nodiscard]] std::optional<Candidate> innerCandidate(cv::Point2d outerCentre,
                                                          double outerSemiMinor,
                                                          double outerInterior, double minR);
    [[nodiscard]] bool measureLevels(const cv::Mat& grey, const Candidate& c, Levels& levels) const;
    // `cells`: grey's BilinearRange, which answers most of the walk's threshold tests.
    // `stride`: every stride-th of the rays (the first pass's coarser fan).
    void castRays(const cv::Mat& grey, const BilinearRange& cells, cv::Point2d from,
                  double maxDistance, const Levels& levels, bool irisOnly = false, int stride = 1);
    // Share of the fitted outline with a dark inside and a brighter outside: `all` counts every
    // sample (the reported confidence, which falls under occlusion); `visible` leaves out the
    // samples where the outline runs through something bright on both sides (an eyelid over the
    // pupil), so candidates are compared on what can be seen: an ellipse shrunk to hug the lid's
    // edge otherwise outscores the true, partly covered pupil.
    struct Support {
        double all = 0.0, visible = 0.0;
        double sharpness = 0.0; // median edge step ratio, 1 = a crisp edge
    };
    struct Refined {
        PupilResult result;
        double visibleSupport = 0.0;
        double quality = 0.0;         // sharpness x filled interior: how much it looks like a pupil
        double interior = 0.0;        // median grey level inside
        double interiorHigh = 0.0;    // its upper quartile (the iris, when a pupil sits inside)
        double outside = -1.0;        // median grey level just outside the outline (-1: unknown)
        double fittedSemiMajor = 0.0; // before fitAtRecentSize: the size the edges chose
        double supportAll = 0.0;      // the whole outline's support (1: nothing covers it)
        double shapeFactor = 1.0;     // the axis-ratio ramp's factor in the confidence
        double fill = 0.0;            // share of dark samples inside (interiorFill)
        double axisRatio = 0.0;       // minor over major axis of the fit
    };
    struct Interior {
        double fill = 0.0, median = 255.0, upperQuartile = 255.0;
    };
    // surroundHint > 0: the grey level known to surround the pupil (the iris it sits in).
    [[nodiscard]] Refined refine(const cv::Mat& grey, const Candidate& c, double minR, double maxR,
                                 double surroundHint = 0.0);
    // A refit without the edge points along a lid over the pupil (a long straight run across
    // the image, off the centre), when the new ellipse reaches beyond the lid; nullopt if there
    // is no lid or no better fit.
    [[nodiscard]] std::optional<EllipseFit> fitBesideLid(const cv::RotatedRect& e,
                                                         const RansacEllipseParams& rp);
    // A refit of the edge points within the recent pupil size when `fit` is clearly larger and
    // the smaller fit explains the points about as well; nullopt otherwise.
    [[nodiscard]] std::optional<EllipseFit> fitAtRecentSize(const cv::Mat& grey,
                                                            const EllipseFit& fit,
                                                            const RansacEllipseParams& rp,
                                                            const Levels& levels) const;
    // A refit of the edge points at least nearly as wide as the recent pupil when `fit` is much
    // narrower (its outline hugging a lid over the pupil) and what the wider ellipse adds lies
    // under something brighter than the iris; nullopt otherwise.
    [[nodiscard]] std::optional<EllipseFit> fitUnderLid(const cv::Mat& grey, const EllipseFit& fit,
                                                        const RansacEllipseParams& rp,
                                                        const Levels& levels) const;
    // Whether `larger`, a refit of `fit` reaching under a lid, is taken: it keeps `keptInliers`
    // of fit's inliers, its visible outline is about as well supported, and what it adds to
    // fit lies under something brighter than the iris (the lid).
    [[nodiscard]] bool addsOnlyLid(const cv::Mat& grey, const EllipseFit& larger,
                                   const EllipseFit& fit, const Levels& levels,
                                   double keptInliers) const;
    // Without a recent pupil to go by: a refit of the edge points that do not face up (a lid
    // over the pupil's top gives edges facing up), at least as round as the pupils a head-mounted
    // camera sees, when `fit` is flatter and what the rounder ellipse adds lies under something
    // brighter than the iris; nullopt otherwise.
    [[nodiscard]] std::optional<EllipseFit> fitRounderUnderLid(const cv::Mat& grey,
                                                               const EllipseFit& fit,
                                                               const RansacEllipseParams& rp,
                                                               const Levels& levels) const;
    // A pupil under the lid placed by its iris: the visible arc of a flat fit and the limbus
    // below it fitted as two concentric ellipses of one shape (limbus_fit.hpp), when that makes
    // the pupil clearly rounder and moves it up; nullopt otherwise. It has no inliers (the arc's
    // points are not mEdgePoints'; nothing after it reads them).
    [[nodiscard]] std::optional<EllipseFit>
    fitWithLimbus(const cv::Mat& grey, const EllipseFit& fit, const Levels& levels) const;
    // A refit of the edge points held to the shape the eye's pupils have at that place
    // (pupil_shape_model.hpp) when `fit`'s shape is well off it, the refit keeps most of its
    // inliers and its visible outline is about as well supported; nullopt otherwise or while the
    // model is not learnt.
    [[nodiscard]] std::optional<EllipseFit> fitToEyeShape(const cv::Mat& grey,
                                                          const EllipseFit& fit,
                                                          const RansacEllipseParams& rp,
                                                          const Levels& levels) const;
    [[nodiscard]] bool isGlint(const cv::Mat& grey, cv::Point2d p, const Levels& levels) const;
    [[nodiscard]] double outsideLevel(const cv::Mat& grey, const cv::RotatedRect& e,
                                      const Levels& levels) const;
    [[nodiscard]] double sizeConsistency(double semiMajor) const;
    // Share of the ellipse's inner area darker than the threshold (glints aside), its median
    // and upper quartile.
    [[nodiscard]] Interior interiorFill(const cv::Mat& grey, const cv::RotatedRect& e,
                                        const Levels& levels) const;
    [[nodiscard]] static double wideOutside(const cv::Mat& grey, cv::Point2d p, cv::Point2d n,
                                            double d, double wide, double in, double out,
                                            const Levels& levels);
    [[nodiscard]] Support outlineSupport(const cv::Mat& grey, const cv::RotatedRect& e,
                                         const Levels& levels) const;

    StarburstConfig mConfig;
    std::vector<cv::Point2d>
        mRayDirections; // unit, one per ray, set once (sincos per ray cost 1 %)
    std::uint64_t mFrame = 0;
    int mBlobsRefined = 0;
    PupilResult mLast;
    AnswerEvidence mEvidence;
    double mRecentRadius = 0.0;   // running pupil size from confident frames, 0 = unknown
    double mRecentMinor = 0.0;    // its minor semi-axis, learnt alike
    double mRecentLevel = -1.0;   // the pupil's inside grey level, learnt alike (-1 = unknown)
    double mRecentContrast = 0.0; // and the step from it to just outside its outline
    int mFramesSinceSize = 0;
    double mEyeRatio = 0.0; // running axis ratio of the whole pupil (0 = unknown)
    PupilShapeModel mShape;
    // Scratch buffers reused between frames (no per-frame allocation in steady state).
    cv::Mat mSmall, mIntegral, mFullIntegral, mSmooth;
    BilinearRange mSmoothRange; // mSmooth's, for the ray walk
    double mNoise = 0.0;        // this frame's sensor noise (grey levels, sigma)
    int mCoarseFactor = 1;      // full-resolution pixels per coarse pixel
    cv::Mat mInnerClipped, mInnerIntegral;
    cv::Mat mClosed, mClosedIntegral, mClosedSmall, mClosedSmallIntegral; // the fallback's search
    std::vector<Candidate> mCandidates, mHeap;
    std::vector<double> mResponses; // one scale's centre-surround responses
    // This frame's first-pass fits, to skip repeats, and whether they were made with a known
    // surround level (a candidate inside an iris): the same first fit with and without the
    // level leads to different second passes.
    struct FirstFit {
        cv::RotatedRect ellipse;
        bool hinted = false;
    };
    std::vector<FirstFit> mFirstFits;
    std::vector<cv::Point2d> mEdgePoints;
    std::vector<cv::Point2d> mEdgeGradients; // unit, dark -> bright; zero when flat
};

} // namespace gt::eyetrack
