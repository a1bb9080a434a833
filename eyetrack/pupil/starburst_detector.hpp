#pragma once
// The default pupil detector (`--detector starburst`) for near-infrared eye images.
//
// Our own code; the ideas are from the published detectors (Starburst, Li, Winfield & Parkhurst
// 2005; Świrski, Bulling & Dodgson 2012; PuRe and PuReST, Santini, Fuhl & Kasneci 2018). Like
// those and ExCuSe/ElSe (Fuhl et al. 2015, 2016) it runs in stages, each in its own file:
//  1. Candidates (candidate_search.hpp): last frame's pupil first (tracking, after PuReST), then
//     the strongest dark blobs of a coarse centre-surround search. When no candidate is
//     confident, further blobs from the image with lashes closed away are tried, and the same
//     search runs inside the winner, inside the best blob by its own evidence and inside an
//     iris-sized candidate that yields no fit, for a pupil in a dark iris.
//  2. Edge points (edge_rays.hpp): the starburst ray walk from each candidate, at a threshold
//     between the pupil's and the iris's levels, glints and edges that do not open onto the iris
//     dropped.
//  3. Ellipse (ellipse_fit.hpp): RANSAC over 5-point conics, refit on the inliers; the rays are
//     recast from the fitted centre and the fit repeated, which evens out the points when the
//     candidate was off-centre. Candidates whose first fit repeats an earlier one's stop there.
//     A fit the lid or lashes left open is refitted by the ordered strategies of
//     refit_strategies.hpp (lid line, recent size, eye shape, limbus).
//  4. Confidence (fit_confidence.hpp): the fitted outline's contrast (PuRe), its sharpness, a
//     filled dark inside, a plausible shape, and size consistency with the recent pupil
//     (PuReST). The candidate with the best score wins, with a preference for last frame's
//     pupil; what is reported is the probability that the answer is right
//     (answer_confidence.hpp).
// Output: sub-pixel centre, ellipse and confidence. Pixel centres are at integer coordinates.
#include <cstdint>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "pupil/answer_confidence.hpp"
#include "pupil/bilinear.hpp"
#include "pupil/candidate_search.hpp"
#include "pupil/edge_rays.hpp"
#include "pupil/ellipse_fit.hpp"
#include "pupil/fit_confidence.hpp"
#include "pupil/image_sampling.hpp"
#include "pupil/pupil_detector.hpp"
#include "pupil/pupil_priors.hpp"

namespace gt::eyetrack {

struct StarburstConfig {
    // Pupil radius bounds in pixels; 0 = from the image's shorter side (3 % .. 25 %).
    double minRadius = 0.0;
    double maxRadius = 0.0;
    // Rays cast from each candidate's fitted centre (the second pass). More rays put more edge
    // points between lashes crossing the pupil's top and between glints on its border, so
    // RANSAC finds the outline's consensus more often; tracking (below) leaves the time for them.
    int rays = 128;
    // The first pass, from the blob's centre, casts this many of them (a divisor of `rays`):
    // its fit only places the second pass's centre and levels, and most blobs end there.
    int seedRays = 64;
    int candidates = 5;
    // When no candidate of the first round reaches `fallbackBelow` confidence (the level at
    // which a pupil is also next frame's prior), up to `fallbackCandidates` further blobs are
    // refined too, their confidence scaled by `fallbackConfidence`: shadows and lash clusters
    // darker than the pupil can fill the first round, but more tries in frames where the pupil
    // may be hidden also give a speck or a lash loop more chances to look like one, and the
    // scale keeps those below the gaze filter's gate. More blobs find more pupils, but also
    // answer confidently in more blinks.
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
    // Plausible pupil shapes for the camera, as the ratio
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
    // uniformly dark inside, the frame's other blobs are not refined: in such frames they almost
    // never win, and refining them is most of a frame's work. 0 = always search.
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
        mPriors.reset();
        mFramesSinceReset = 0;
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
    using Candidate = starburst::Candidate;
    // A candidate refined: its fit and what was measured on it. result.confidence is the
    // detector's own (FitEvidence::confidence; consider() applies the size prior to it).
    struct Refined : starburst::FitEvidence {
        PupilResult result;
        double fittedSemiMajor = 0.0; // before refits held to the recent size: the edges' choice
        double inlierShare = 0.0; // the second ray pass's edge points within inlierDistance of it
    };
    // A refined candidate and how it was ranked.
    struct Scored : Refined {
        double score = 0.0;
        double consistency = 1.0; // the size prior's factor in score and confidence
        double sizeFactor = 1.0;  // the size prior's factor in the confidence alone
        double frameScore = 0.0;  // the score without its history factors (size, last pupil)
    };
    // What detect() knows of the frame it works on.
    struct Frame {
        const cv::Mat& grey;
        double minR = 0.0, maxR = 0.0; // pupil radius bounds, px
        double side = 0.0;             // the image's shorter side, px
        bool haveLast = false;         // last frame's pupil is a candidate
    };
    // The first ray pass and fit from a candidate.
    struct FirstPass {
        starburst::RayLevels levels;
        RansacEllipseParams ransac;
        EllipseFit fit;
    };
    // The pick and whether a darker blob inside it lost to it (then it may be an iris).
    struct Pick {
        const Scored* scored = nullptr;
        bool darkerInside = false;
    };

    // The frame's integral image, smoothed copy, noise and first round of candidates.
    void prepare(const Frame& frame);
    // Refines the candidates in order (last frame's pupil first), the fallback round when the
    // first finds nothing confident; the strongest iris-sized candidate that yields no fit is
    // returned, for the search inside it.
    [[nodiscard]] std::optional<Candidate> searchCandidates(const Frame& frame);
    // Whether last frame's pupil, refined first, was found again well enough to stop there.
    [[nodiscard]] bool tracked(const Scored& prior) const;
    // The searches inside an unfitted iris-sized candidate, the winner and the best blob by its
    // own evidence, mScored sorted by score after them; the winner's centre when a clearly
    // darker blob was found inside it.
    std::optional<cv::Point2d> searchInside(const Frame& frame,
                                            const std::optional<Candidate>& unfitted);
    [[nodiscard]] Pick pickPupil(const std::optional<cv::Point2d>& darkerBlobIn) const;
    // Whether s, inside the winner `outer`, is a pupil in the iris that should replace it; sets
    // darkerInside when s is a darker blob in it that does not.
    [[nodiscard]] bool isPupilInside(const Scored& s, const Scored& outer,
                                     bool& darkerInside) const;
    // The answer's evidence, the reported result, and the priors' learning.
    [[nodiscard]] PupilResult report(const Pick& pick);
    // Refines candidate c and scores it into mScored (confidenceScale: StarburstConfig::
    // fallbackConfidence for the fallback round's blobs).
    void consider(const Frame& frame, const Candidate& c, double surroundHint,
                  double confidenceScale = 1.0);
    // surroundHint > 0: the grey level known to surround the pupil (the iris it sits in).
    [[nodiscard]] Refined refine(const cv::Mat& grey, const Candidate& c, double minR, double maxR,
                                 double surroundHint = 0.0);
    [[nodiscard]] std::optional<FirstPass> firstPass(const cv::Mat& grey, const Candidate& c,
                                                     double minR, double maxR, double surroundHint);
    // The axis-ratio ramp's factor on the configured ramp (StarburstConfig::flattestAxisRatio,
    // roundAxisRatio), without what this eye's pupils have taught: the shape as a single image
    // shows it.
    [[nodiscard]] double ownShapeFactor(double axisRatio) const {
        return starburst::smoothstep(mConfig.flattestAxisRatio, mConfig.roundAxisRatio, axisRatio);
    }
    [[nodiscard]] starburst::RayImage rayImage() const {
        return {mSmooth, mSmoothRange, mFullIntegral};
    }

    StarburstConfig mConfig;
    starburst::CandidateSearch mSearch;
    starburst::EdgeRays mRays;
    starburst::PupilPriors mPriors;
    std::uint64_t mFrame = 0; // frames ever seen (the RANSAC seeds follow it, reset or not)
    std::uint64_t mFramesSinceReset = 0;
    int mBlobsRefined = 0;
    PupilResult mLast;
    AnswerEvidence mEvidence;
    // Scratch buffers reused between frames (no per-frame allocation in steady state).
    cv::Mat mFullIntegral, mSmooth;
    BilinearRange mSmoothRange; // mSmooth's, for the ray walk
    double mNoise = 0.0;        // this frame's sensor noise (grey levels, sigma)
    std::vector<Candidate> mCandidates;
    std::vector<Scored> mScored; // this frame's refined candidates
    // This frame's first-pass fits, to skip repeats, and whether they were made with a known
    // surround level (a candidate inside an iris): the same first fit with and without the
    // level leads to different second passes.
    struct FirstFit {
        cv::RotatedRect ellipse;
        bool hinted = false;
    };
    std::vector<FirstFit> mFirstFits;
};

} // namespace gt::eyetrack
