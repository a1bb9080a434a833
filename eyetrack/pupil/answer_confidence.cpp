#include "pupil/answer_confidence.hpp"

#include <algorithm>
#include <cmath>

namespace gt::eyetrack {

double answerProbability(const AnswerEvidence& e) {
    if (!(e.confidence > 0.0)) {
        return 0.0;
    }
    // Logistic regression (Newton's method, 1e-3 ridge) of "within 5 px of the true centre"
    // on the detector's answers (the pupil at least half visible; any answer on a hidden pupil
    // is wrong) over synthetic clips of the wild and hard presets (`eyescore --answers`,
    // scripts/fit_answer_confidence.py), checked on clips it was not fitted on. Inputs that would
    // tie it to one generator's exposure and scale (the pupil's grey level, its size in pixels)
    // are left out although they separate better still, and so are those the others make
    // redundant (the whole outline's support, the sharpness on its own, the inside's spread,
    // whether a darker blob inside lost to the answer). The axis ratio is taken against the
    // eye's own (StarburstConfig::eyeRatioMargin) once learnt: the raw ratio puts right answers
    // on an eye seen from the side under the gate. The inside's level against the pupil's recent
    // one separates a lash clump or a shadow on the lid, answered while the pupil is under it,
    // which fits as well as a pupil but is brighter. The product's own weight is about nil: what
    // it multiplies is in the other inputs. Refit whenever the detector changes what it measures.
    constexpr double kBias = -16.764;
    constexpr double kLogConfidence = -0.017;
    constexpr double kVisibleSupport = 4.250;
    constexpr double kFill = 5.747;
    constexpr double kAxisRatio = 7.148;
    constexpr double kLogSizeFactor = 0.833;
    constexpr double kScore = 4.310;
    constexpr double kRivalRatio = -0.186;   // rival's score over the answer's, at most 2
    constexpr double kLastDistance = -1.140; // in semi-major axes, at most 3
    constexpr double kNoLast = -0.821;
    constexpr double kSizeKnown = 1.869;
    constexpr double kLevelExcess = -5.435; // AnswerEvidence::levelExcess, at most 3
    const double rival = e.score > 0.0 ? std::min(2.0, e.rivalScore / e.score) : 0.0;
    const bool noLast = e.lastDistance < 0.0;
    const double last = noLast ? 0.0 : std::min(3.0, e.lastDistance / std::max(1.0, e.semiMajor));
    const double z = kBias + kLogConfidence * std::log(std::max(1e-3, e.confidence)) +
                     kVisibleSupport * e.visibleSupport + kFill * e.fill +
                     kAxisRatio * e.axisRatio +
                     kLogSizeFactor * std::log(std::max(1e-3, e.sizeFactor)) + kScore * e.score +
                     kRivalRatio * rival + kLastDistance * last + (noLast ? kNoLast : 0.0) +
                     (e.sizeKnown ? kSizeKnown : 0.0) + kLevelExcess * e.levelExcess;
    return 1.0 / (1.0 + std::exp(-z));
}

} // namespace gt::eyetrack
