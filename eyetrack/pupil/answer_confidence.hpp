#pragma once
// The confidence the detector reports: the probability that its answer is within 5 px of the
// pupil's centre, from what it measured on the answer (logistic calibration in the manner of
// Platt scaling). Its logit is the sum of two parts:
//  - the frame's own evidence, all a first frame has (a recording's start, the frame after a
//    reset, a still image): how much of the fitted outline has an edge, how many of the ray
//    walk's edge points lie on the fit, how dark and filled the inside is against the noise,
//    how round the fit is, the detector's product of factors without its priors, and whether
//    another place scored nearly as well;
//  - what the history adds, nil without one: once the detector has seen earlier frames, the
//    answer is judged as ordinary runs calibrate it (whether it continues the last
//    answer, agrees with the recent size, is as dark inside as the pupil has lately been, is as
//    round as this eye's whole pupils, whether earlier frames taught it a pupil at all, and the
//    frame's evidence as the priors ranked it), which adds assurance where the history agrees
//    and doubt where it does not. A clear pupil does not need it to pass the gaze filter's gate.
// Fitted on synthetic clips (see answer_confidence.cpp).
#include <cstdint>

namespace gt::eyetrack {

struct AnswerEvidence {
    // The frame's own evidence.
    double confidence = 0.0;     // the detector's product of factors, no size prior (0: no answer)
    double visibleSupport = 0.0; // share of the visible outline with an outward edge
    double supportAll = 0.0;     // share of the whole outline with one (1: nothing covers it)
    double fill = 0.0;           // share of dark samples inside the ellipse
    double axisRatio = 0.0;      // minor over major axis of the fit
    double score = 0.0;          // the selection score, its history factors left out
    double rivalScore = 0.0;     // the best such score elsewhere in the image (0: none)
    double inlierShare = 0.0;    // share of the ray walk's edge points on the fit (within 1 px)
    double contrast = 0.0;       // outside minus inside level over the frame's noise sigma
    double semiMajor = 0.0;      // px
    // What the history adds (the defaults: none).
    // Frames the detector saw since it was last reset, before this one (0: a first frame). Seen
    // frames that taught it nothing are history too: a pupil that was not found confidently
    // for a while is less likely to be right now.
    std::uint64_t earlierFrames = 0;
    // The axis ratio over the eye's own whole-pupil ratio, at most 1 (0: not learnt).
    double eyeAxisRatio = 0.0;
    double sizeFactor = 1.0; // the size prior's factor (1 without a prior)
    // The product, the selection score and the best score elsewhere as the detector ranked
    // them, its priors applied (the size prior, the eye's own shape, the last pupil's
    // preference); the same as the frame's own above when it has no history.
    double rankedConfidence = 0.0;
    double rankedScore = 0.0;
    double rankedRivalScore = 0.0;
    bool sizeKnown = false;     // a recent pupil size has been learnt
    double lastDistance = -1.0; // px from the last frame's answer (-1: there was none)
    // How much brighter the answer's inside is than the pupil has lately been, in recent
    // pupil-to-outside contrasts: 0 when no level is learnt or it is no brighter, at most 3.
    double levelExcess = 0.0;
};

// Whether e carries any history (earlier frames, a last answer, a learnt size, level or shape).
[[nodiscard]] bool hasHistory(const AnswerEvidence& e);
// The logit of the frame's own evidence alone (what a frame without history is judged on).
[[nodiscard]] double frameLogit(const AnswerEvidence& e);
// What the history adds to it, up (it agrees) or down (it doubts): 0 without history.
[[nodiscard]] double historyLogit(const AnswerEvidence& e);
// In [0, 1); 0 when there is no answer (confidence <= 0).
[[nodiscard]] double answerProbability(const AnswerEvidence& e);

} // namespace gt::eyetrack
