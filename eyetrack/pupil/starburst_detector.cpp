#include "pupil/starburst_detector.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <span>

#include <opencv2/imgproc.hpp>

#include "error.hpp"
#include "pupil/box_blur.hpp"
#include "pupil/image_sampling.hpp"
#include "pupil/refit_strategies.hpp"

namespace gt::eyetrack {

using starburst::boxAround;
using starburst::percentile;

namespace {

// A candidate at least this many times the smallest pupil radius is iris-sized: when it yields no
// fit, the pupil is looked for inside it.
constexpr double kIrisSized = 3.0;

// The share of the edge points within 1 px (Sampson distance) of ellipse e: the fit's residual
// as a frame's own evidence. A pupil's rays end on its outline nearly all round; a lash loop's
// or a shadow's scatter. The refits place some fits from fewer points (a lid line dropped, a
// limbus), so it is measured on the final ellipse rather than taken from RANSAC's consensus.
double inlierShare(const cv::RotatedRect& e, std::span<const cv::Point2d> points) {
    if (points.empty()) {
        return 0.0;
    }
    const Conic q = Conic::fromEllipse(e);
    const auto on = std::count_if(points.begin(), points.end(),
                                  [&](cv::Point2d p) { return q.sampsonDistance(p) <= 1.0; });
    return static_cast<double>(on) / static_cast<double>(points.size());
}

} // namespace

StarburstDetector::StarburstDetector(StarburstConfig config)
    : mConfig(config), mSearch(config.minContrast), mRays(std::max(config.rays, 0)) {
    if (mConfig.rays < 8) throw EyetrackError("pupil detector: at least 8 rays are needed");
    if (mConfig.seedRays < 8 || mConfig.rays % mConfig.seedRays != 0) {
        throw EyetrackError("pupil detector: seedRays must be at least 8 and divide rays");
    }
    if (mConfig.candidates < 1) {
        throw EyetrackError("pupil detector: at least 1 candidate is needed");
    }
    if (mConfig.fallbackCandidates < 0) {
        throw EyetrackError("pupil detector: fallback candidates cannot be negative");
    }
    if (mConfig.fallbackClosing < 0.0) {
        throw EyetrackError("pupil detector: fallbackClosing must be 0 (off) or more");
    }
    if (mConfig.eyeRatioMargin < 0.0) {
        throw EyetrackError("pupil detector: the eye's axis-ratio margin cannot be negative");
    }
}

std::optional<StarburstDetector::FirstPass> StarburstDetector::firstPass(const cv::Mat& grey,
                                                                         const Candidate& c,
                                                                         double minR, double maxR,
                                                                         double surroundHint) {
    auto levels = starburst::measureLevels(grey, c, mConfig.minContrast, mNoise);
    if (!levels) return std::nullopt;
    starburst::RayLevels& lv = *levels;
    if (surroundHint > 0.0 && surroundHint < lv.surround) {
        // A pupil inside a dark iris: the ring around the seed reaches the sclera, but what
        // borders the pupil is the iris.
        lv.surround = surroundHint;
        if (lv.surround - lv.pupil < 0.5 * mConfig.minContrast) return std::nullopt;
        lv.threshold = 0.5 * (lv.pupil + lv.surround);
    }
    RansacEllipseParams rp;
    rp.iterations = mConfig.ransacIterations;
    rp.inlierDistance = mConfig.inlierDistance;
    rp.minAxis = 2.0 * minR * 0.7;
    rp.maxAxis = 2.0 * maxR * 1.3;
    rp.seed = mFrame * 7919u + 1u;
    // The first pass only places the second pass's centre and levels: a coarser fan of rays.
    mRays.cast(rayImage(), c.centre, 2.5 * c.radius, lv, false, mConfig.rays / mConfig.seedRays);
    auto fit = fitEllipseRansac(mRays.points(), rp, mRays.gradients());
    if (!fit) return std::nullopt;
    // Candidates on the same blob (the last frame's pupil and the search's, a blob found at
    // two scales) reach the same first fit; what follows would only repeat that candidate's.
    // Not across a surround hint: a pupil in a dark iris, looked for with the iris's level,
    // can have the same first fit as the same blob found by the search without it, but the
    // hinted second pass thresholds at the iris's level and can find an outline the other
    // did not.
    const cv::RotatedRect& first = fit->ellipse;
    const bool hinted = surroundHint > 0.0;
    const bool seen = std::any_of(mFirstFits.begin(), mFirstFits.end(), [&](const FirstFit& o) {
        const cv::RotatedRect& e = o.ellipse;
        return o.hinted == hinted &&
               std::hypot(e.center.x - first.center.x, e.center.y - first.center.y) < 1.0 &&
               std::abs(e.size.width - first.size.width) < 1.0 &&
               std::abs(e.size.height - first.size.height) < 1.0;
    });
    if (seen) {
        return std::nullopt;
    }
    mFirstFits.push_back({first, hinted});
    return FirstPass{lv, rp, std::move(*fit)};
}

StarburstDetector::Refined StarburstDetector::refine(const cv::Mat& grey, const Candidate& c,
                                                     double minR, double maxR,
                                                     double surroundHint) {
    Refined refined;
    auto first = firstPass(grey, c, minR, maxR, surroundHint);
    if (!first) return refined;
    starburst::RayLevels& lv = first->levels;
    RansacEllipseParams& rp = first->ransac;
    EllipseFit fit = std::move(first->fit);
    // Second pass from the fitted centre: rays now meet the boundary at even spacing, and the
    // threshold sits half-way to the level measured just outside the first fit (the iris).
    const cv::Point2d centre(fit.ellipse.center.x, fit.ellipse.center.y);
    const double major = 0.5 * std::max(fit.ellipse.size.width, fit.ellipse.size.height);
    bool irisMeasured = false;
    if (const double outside = starburst::outsideLevel(grey, fit.ellipse, lv);
        outside > lv.pupil + mConfig.minContrast) {
        lv.surround = outside;
        lv.threshold = 0.5 * (lv.pupil + outside);
        irisMeasured = true;
    }
    mRays.cast(rayImage(), centre, 1.6 * major + 3.0, lv, irisMeasured);
    rp.seed += 1;
    if (auto second = fitEllipseRansac(mRays.points(), rp, mRays.gradients())) fit = *second;
    const starburst::RefitContext ctx{grey, mSmooth, mRays.points(), mRays.gradients(),
                                      lv,   rp,      mPriors};
    const starburst::Refitted refitted = starburst::applyRefits(ctx, std::move(fit));
    refined.fittedSemiMajor = refitted.fittedSemiMajor;
    refined.result.ellipse = refitted.fit.ellipse;
    const double round =
        starburst::roundAxisRatio(mConfig.roundAxisRatio, mConfig.flattestAxisRatio,
                                  mConfig.eyeRatioMargin, mPriors.eyeRatio);
    static_cast<starburst::FitEvidence&>(refined) =
        starburst::judgeFit(grey, refitted.fit.ellipse, lv, mConfig.flattestAxisRatio, round);
    refined.result.confidence = refined.confidence;
    refined.inlierShare = inlierShare(refitted.fit.ellipse, mRays.points());
    return refined;
}

void StarburstDetector::consider(const Frame& frame, const Candidate& c, double surroundHint,
                                 double confidenceScale) {
    ++mBlobsRefined;
    Refined refined = refine(frame.grey, c, frame.minR, frame.maxR, surroundHint);
    PupilResult& r = refined.result;
    if (r.confidence <= 0.0 && refined.visibleSupport <= 0.0) return;
    // Size consistency (PuReST): the pupil's size changes slowly, so an ellipse far from the
    // recent pupil size (a gap between lashes during a blink) loses confidence.
    const double consistency = starburst::sizeConsistency(r.semiMajor(), mPriors.recentRadius);
    const double sizeFactor =
        starburst::sizeConsistency(refined.fittedSemiMajor, mPriors.recentRadius);
    r.confidence *= sizeFactor;
    r.confidence *= confidenceScale;
    // Selection score: support of the visible outline and how pupil-like the ellipse is,
    // weighed towards pupil-sized ellipses (dark gaps between lashes make small, high-contrast
    // ellipses), towards a shape the camera can see a pupil at (the square root of the
    // confidence's axis-ratio ramp: a flat lash loop or a sliver of the lid's margin must not
    // outscore a rounder pupil of a little less support) and towards last frame's pupil.
    double score = refined.visibleSupport * refined.quality * consistency *
                   std::sqrt(refined.shapeFactor) *
                   (0.6 + 0.4 * std::min(1.0, r.semiMinor() / (0.06 * frame.side)));
    if (frame.haveLast &&
        cv::norm(r.centre() - mLast.centre()) < std::max(5.0, 0.5 * mLast.semiMajor()))
        score *= 1.2;
    if (score > 0.0) {
        // The same score from the frame alone: no size prior, no last pupil, the shape judged on
        // the configured ramp rather than the one this eye's pupils taught.
        const double ownShape = ownShapeFactor(refined.axisRatio);
        const double frameScore = refined.visibleSupport * refined.quality * std::sqrt(ownShape) *
                                  (0.6 + 0.4 * std::min(1.0, r.semiMinor() / (0.06 * frame.side)));
        mScored.push_back({refined, score, consistency, sizeFactor, frameScore});
    }
}

void StarburstDetector::prepare(const Frame& frame) {
    const cv::Mat& grey = frame.grey;
    cv::integral(grey, mFullIntegral, CV_32S);
    mCandidates.clear();
    // With the closing, the fallback round's blobs are searched for only when it runs.
    const int plainBlobs =
        mConfig.candidates + (mConfig.fallbackClosing > 0.0 ? 0 : mConfig.fallbackCandidates);
    mSearch.find(grey, mFullIntegral, frame.minR, frame.maxR, mCandidates,
                 static_cast<std::size_t>(plainBlobs));
    mFirstFits.clear();
    // Rays walk a 3x3 box-filtered copy: sensor noise would otherwise end a ray at the first
    // noisy pixel above the threshold when the pupil is only a little darker than its iris. The
    // filter is symmetric, so the half-way crossing of an edge stays where it was.
    boxBlur3x3(grey, mSmooth);
    mNoise = starburst::noiseSigma(grey, mSmooth);
    mSmoothRange.build(mSmooth);
    // Temporal prior (after PuReST, Santini et al. 2018): last frame's pupil is also a candidate,
    // and a result close to it is preferred. Pupils move little between frames except in
    // saccades, where the coarse search still finds them.
    if (frame.haveLast) {
        mCandidates.insert(mCandidates.begin(), {mLast.centre(), mLast.semiMajor(), 0.0});
    }
}

bool StarburstDetector::tracked(const Scored& prior) const {
    // Tracking (as PuReST tracks before it searches): when last frame's pupil, refined first, is
    // found again where it was with a confident, well-outlined, uniformly dark fit, the other
    // blobs are not refined — in such frames they almost never win, and they are two thirds of
    // the work. The inner-blob searches still run on it.
    return prior.result.confidence >= mConfig.trackingConfidence &&
           prior.visibleSupport >= mConfig.trackingSupport &&
           prior.interiorHigh - prior.interior < 0.5 * mConfig.minContrast &&
           cv::norm(prior.result.centre() - mLast.centre()) <
               std::max(5.0, 0.5 * mLast.semiMajor());
}

std::optional<StarburstDetector::Candidate>
StarburstDetector::searchCandidates(const Frame& frame) {
    // The strongest iris-sized candidate that yields no fit (a dark iris cut by the lid, its
    // outline broken by glints and lashes): its pupil is a weak blob inside a dark surround that
    // the search ranks below lash clusters, so it is looked for inside that candidate too.
    std::optional<Candidate> unfitted;
    const std::size_t firstRound =
        std::min(mCandidates.size(),
                 static_cast<std::size_t>(mConfig.candidates) + (frame.haveLast ? 1U : 0U));
    for (std::size_t i = 0; i <= mCandidates.size(); ++i) {
        if (i == firstRound && mConfig.fallbackCandidates > 0) {
            // The fallback round (StarburstConfig::fallbackCandidates): further blobs when the
            // first round found nothing as confident as a prior. Blurred shadows and lash
            // clusters outside the eye, darker than the pupil and so stronger blobs, can take
            // every place of the first round while a low-contrast pupil is plainly visible.
            if (std::any_of(mScored.begin(), mScored.end(), [&](const Scored& s) {
                    return s.result.confidence >= mConfig.fallbackBelow;
                })) {
                break;
            }
            if (mConfig.fallbackClosing > 0.0) {
                // StarburstConfig::fallbackClosing; the first round keeps the plain image's
                // blobs, where a pupil only a little darker than its iris is a blob of its own
                // (closed, it can merge with the iris), and the closing is paid only in the
                // frames that reach this round.
                const int side =
                    2 * static_cast<int>(0.5 * mConfig.fallbackClosing * frame.minR) + 1;
                mCandidates.resize(firstRound);
                mSearch.findClosed(frame.grey, side, frame.minR, frame.maxR, mCandidates,
                                   firstRound +
                                       static_cast<std::size_t>(mConfig.fallbackCandidates));
            }
        }
        if (i == mCandidates.size()) {
            break;
        }
        const Candidate& c = mCandidates[i];
        const std::size_t before = mScored.size();
        consider(frame, c, 0.0, i < firstRound ? 1.0 : mConfig.fallbackConfidence);
        if (i == 0 && frame.haveLast && mConfig.trackingConfidence > 0.0 &&
            mScored.size() > before && tracked(mScored.back())) {
            break;
        }
        if (mScored.size() == before && !unfitted && c.radius >= kIrisSized * frame.minR) {
            unfitted = c;
        }
    }
    return unfitted;
}

std::optional<cv::Point2d>
StarburstDetector::searchInside(const Frame& frame, const std::optional<Candidate>& unfitted) {
    if (unfitted) {
        // The iris's level: the upper quartile of its inner box (the pupil and glints aside).
        const double level = percentile(
            frame.grey, boxAround(unfitted->centre, 0.7 * unfitted->radius), cv::Rect(), 0.75);
        if (level > 0.0) {
            if (const auto inner =
                    mSearch.inside(unfitted->centre, unfitted->radius, level, frame.minR)) {
                consider(frame, *inner, level);
            }
        }
    }
    const auto byScore = [](const Scored& a, const Scored& b) { return a.score > b.score; };
    std::sort(mScored.begin(), mScored.end(), byScore);
    if (mScored.empty()) {
        return std::nullopt;
    }
    // The search keeps the strongest blobs, and a dark iris's contrast with the sclera can crowd
    // the pupil inside it out: look for the darkest blob inside the winner too, with the
    // winner's inside as the level around it. The same for the best blob by its own evidence,
    // without the size prior: an iris whose pupil was too faint to be a candidate loses to
    // smaller blobs once the prior holds the pupil's size, and its pupil would not be looked for
    // at all.
    const Scored top = mScored.front();
    const auto unscaled =
        std::max_element(mScored.begin(), mScored.end(), [](const Scored& a, const Scored& b) {
            return a.score / a.consistency < b.score / b.consistency;
        });
    const std::optional<Scored> ownBest = unscaled->consistency < 1.0 && unscaled != mScored.begin()
                                              ? std::optional<Scored>(*unscaled)
                                              : std::nullopt;
    // A blob clearly darker than what surrounds it inside the winner: the winner is not
    // uniformly dark, whatever its inside's quartiles say (a small pupil covers too few of
    // their samples to move them).
    bool blobInsideTop = false;
    if (const auto inner = mSearch.inside(top.result.centre(), top.result.semiMinor(),
                                          top.interiorHigh, frame.minR)) {
        blobInsideTop = inner->response >= mConfig.minContrast;
        consider(frame, *inner, top.interiorHigh);
    }
    if (ownBest) {
        if (const auto inner = mSearch.inside(ownBest->result.centre(), ownBest->result.semiMinor(),
                                              ownBest->interiorHigh, frame.minR)) {
            consider(frame, *inner, ownBest->interiorHigh);
        }
    }
    std::sort(mScored.begin(), mScored.end(), byScore);
    return blobInsideTop ? std::optional<cv::Point2d>(top.result.centre()) : std::nullopt;
}

bool StarburstDetector::isPupilInside(const Scored& s, const Scored& outer,
                                      bool& darkerInside) const {
    // Inside: within 0.7 of the way from the outer ellipse's centre to its outline (a lash
    // cluster on the rim of a dark iris is not a pupil in it).
    const cv::RotatedRect& oe = outer.result.ellipse;
    const double th = oe.angle * std::numbers::pi / 180.0;
    const double ca = std::cos(th), sa = std::sin(th);
    const double oa = 0.5 * oe.size.width, ob = 0.5 * oe.size.height;
    const cv::Point2d d = s.result.centre() - outer.result.centre();
    const double u = (d.x * ca + d.y * sa) / oa, v = (-d.x * sa + d.y * ca) / ob;
    const bool inside = u * u + v * v < 0.49;
    const bool smaller = s.result.semiMajor() < 0.75 * outer.result.semiMajor();
    // Its outline must be a step of the full contrast, not a ripple inside a pupil (a glint's
    // halo lifts the outer blob's brightest quarter).
    if (!inside || !smaller || s.interior >= outer.interiorHigh - 0.5 * mConfig.minContrast ||
        s.outside < s.interior + mConfig.minContrast || s.visibleSupport < 0.5) {
        return false;
    }
    // What rings it must be what fills the winner (a pupil's iris), not something brighter: a
    // small fit at the rim of a plainly seen pupil, its outside half iris and half glint halo
    // (several glints inside the pupil), would otherwise pass as a darker blob inside, take the
    // winner's place, and tracking would hold it.
    if (s.outside > outer.interiorHigh + 0.5 * mConfig.minContrast) {
        return false;
    }
    // Lid skin inside a pupil whose top is under the lid lifts its upper quartile as an iris
    // would; a part of that pupil is no darker than most of it, though, while a pupil in its iris
    // is (it fills less than half the iris's inside) or, when it is large, is ringed by the iris
    // and so mostly seen. Visible support alone would keep a small pupil whose glints break up
    // its outline out of its iris.
    const bool darkerThanMost = s.interior < outer.interior - 0.5 * mConfig.minContrast;
    if ((darkerThanMost || s.visibleSupport >= 0.7) && s.result.confidence >= 0.5 &&
        s.score >= 0.5 * outer.score) {
        return true;
    }
    darkerInside = true;
    return false;
}

StarburstDetector::Pick
StarburstDetector::pickPupil(const std::optional<cv::Point2d>& darkerBlobIn) const {
    Pick pick;
    if (mScored.empty()) {
        return pick;
    }
    // The pupil is the darkest blob: a clearly darker, well-outlined ellipse inside the winner (a
    // pupil only slightly darker than its dark iris, which outscores it on contrast with the
    // sclera) takes its place. One that loses only on its score still shows the pick to be an
    // iris around a pupil: the size prior must not learn the pick's size (report()).
    const Scored* outer = &mScored.front();
    pick.scored = outer;
    for (const Scored& s : mScored) {
        if (&s != outer && isPupilInside(s, *outer, pick.darkerInside)) {
            pick.scored = &s;
            break;
        }
    }
    // The winner kept with a clearly darker blob inside it may be an iris around a pupil the
    // fits did not outline well enough to take its place: its size must not become the pupil's.
    // Once learnt, the prior would veto the pupil's own later, good fits as too small.
    if (darkerBlobIn && cv::norm(pick.scored->result.centre() - *darkerBlobIn) < 0.5) {
        pick.darkerInside = true;
    }
    return pick;
}

PupilResult StarburstDetector::report(const Pick& pick) {
    // The pick with what was measured on it; when nothing was scored, a default (no pupil, the
    // priors learn nothing).
    const Scored none{};
    const Scored* picked = pick.scored ? pick.scored : &none;
    PupilResult best = picked->result;
    best.found = best.confidence >= mConfig.minConfidence;
    // What is reported is the probability that the answer is right (answer_confidence.hpp); the
    // detector's own product of factors stays what its priors and the next frame's search go by
    // (they were designed on its scale).
    // The frame's own evidence first (all a first frame has): the product without the size
    // prior's factor and with the shape judged on the configured ramp, not the eye's own.
    const double eyeRatio = mPriors.eyeRatio;
    const double frameProduct = picked->shapeFactor > 0.0
                                    ? best.confidence / std::max(1e-12, picked->sizeFactor) *
                                          ownShapeFactor(picked->axisRatio) / picked->shapeFactor
                                    : 0.0;
    mEvidence = AnswerEvidence{
        .confidence = frameProduct,
        .visibleSupport = picked->visibleSupport,
        .supportAll = picked->supportAll,
        .fill = picked->fill,
        .axisRatio = picked->axisRatio,
        .score = picked->frameScore,
        .inlierShare = picked->inlierShare,
        .contrast = picked->outside >= 0.0
                        ? std::max(0.0, picked->outside - picked->interior) / std::max(1.0, mNoise)
                        : 0.0,
        .semiMajor = best.semiMajor(),
        .earlierFrames = mFramesSinceReset - 1,
        .eyeAxisRatio = eyeRatio > 0.0 ? std::min(1.0, picked->axisRatio / eyeRatio) : 0.0,
        .sizeFactor = picked->sizeFactor,
        .rankedConfidence = best.confidence,
        .rankedScore = picked->score,
        .sizeKnown = mPriors.recentRadius > 0.0};
    // A rival: the best candidate at another place (not the same blob found twice).
    for (const Scored& s : mScored) {
        if (&s != picked &&
            cv::norm(s.result.centre() - best.centre()) >= std::max(5.0, 0.5 * best.semiMajor())) {
            mEvidence.rivalScore = std::max(mEvidence.rivalScore, s.frameScore);
            mEvidence.rankedRivalScore = std::max(mEvidence.rankedRivalScore, s.score);
        }
    }
    if (mLast.found) {
        mEvidence.lastDistance = cv::norm(best.centre() - mLast.centre());
    }
    if (mPriors.recentLevel >= 0.0 && picked->outside >= 0.0) {
        mEvidence.levelExcess =
            std::clamp((picked->interior - mPriors.recentLevel) /
                           std::max(mConfig.minContrast, mPriors.recentContrast),
                       0.0, 3.0);
    }
    PupilResult reported = best;
    reported.confidence = answerProbability(mEvidence);
    reported.found = reported.confidence >= mConfig.minConfidence;
    mLast = best;
    mPriors.learn(starburst::PickedAnswer{.result = best,
                                          .sizeFactor = picked->sizeFactor,
                                          .shapeFactor = picked->shapeFactor,
                                          .supportAll = picked->supportAll,
                                          .interior = picked->interior,
                                          .outside = picked->outside,
                                          .uniform = picked->interiorHigh - picked->interior <
                                                         0.5 * mConfig.minContrast &&
                                                     !pick.darkerInside},
                  mConfig.eyeRatioMargin);
    return reported;
}

PupilResult StarburstDetector::detect(const cv::Mat& grey, double /*tMs*/) {
    if (grey.empty() || grey.type() != CV_8UC1)
        throw EyetrackError("pupil detector: expected an 8-bit greyscale image");
    ++mFrame;
    ++mFramesSinceReset;
    mBlobsRefined = 0;
    const double side = std::min(grey.rows, grey.cols);
    const Frame frame{.grey = grey,
                      .minR = mConfig.minRadius > 0.0 ? mConfig.minRadius : 0.03 * side,
                      .maxR = mConfig.maxRadius > 0.0 ? mConfig.maxRadius : 0.25 * side,
                      .side = side,
                      .haveLast = mLast.found && mLast.confidence >= 0.6};
    mScored.clear();
    prepare(frame);
    const std::optional<Candidate> unfitted = searchCandidates(frame);
    const std::optional<cv::Point2d> darkerBlobIn = searchInside(frame, unfitted);
    return report(pickPupil(darkerBlobIn));
}

} // namespace gt::eyetrack
