#pragma once
// The confidence the detector reports: the probability that its answer is within 5 px of the
// pupil's centre, from what it measured on the answer (logistic calibration in the manner of
// Platt scaling). The product of factors that ranks candidates inside the detector (outline
// support, sharpness, filled inside, shape, size prior) is one input; the others are what the
// product leaves out or weighs by hand: how much of the outline is seen, how dark the inside is,
// how round the fit is, whether another place scored nearly as well, whether the answer
// continues the last one, and whether its inside is as dark as the pupil has lately been. Fitted on
// synthetic clips (see answer_confidence.cpp).

namespace gt::eyetrack {

struct AnswerEvidence {
    double confidence = 0.0;     // the detector's own product of factors (0: no answer)
    double visibleSupport = 0.0; // share of the visible outline with an outward edge
    double fill = 0.0;           // share of dark samples inside the ellipse
    // Minor over major axis of the fit; over the eye's own whole-pupil ratio (at most 1) once
    // the detector has learnt that.
    double axisRatio = 0.0;
    double sizeFactor = 1.0;    // the size prior's factor (1 without a prior)
    bool sizeKnown = false;     // a recent pupil size has been learnt
    double score = 0.0;         // the selection score that picked the answer
    double rivalScore = 0.0;    // the best score elsewhere in the image (0: none)
    double lastDistance = -1.0; // px from the last frame's answer (-1: there was none)
    double semiMajor = 0.0;     // px
    // How much brighter the answer's inside is than the pupil has lately been, in recent
    // pupil-to-outside contrasts: 0 when no level is learnt or it is no brighter, at most 3.
    double levelExcess = 0.0;
};

// In [0, 1); 0 when there is no answer (confidence <= 0).
[[nodiscard]] double answerProbability(const AnswerEvidence& e);

} // namespace gt::eyetrack
