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
    // is wrong) over eyesim development seeds only: wild 1-300 and hard 1-200, 300 frames each
    // from 1560, 149,967 answers (`eyescore --answers`, scripts/fit_answer_confidence.py).
    // Fitted on one half (wild 1-150, hard 1-100), the ROC area on the other half rose from
    // 0.9928 (the product alone) to 0.9964, the other way round from 0.9930 to 0.9965, and on
    // wild 151-300 alone from 0.9860 to 0.9930. Inputs that would tie it to one generator's
    // exposure and scale (the pupil's grey level, its size in pixels) were left out although
    // they separated better still (0.9946 on wild 151-300 in a first fit), and so were those
    // the others made redundant (the whole outline's support, the sharpness on its own).
    // Refitted for 128 rays (starburst_detector.hpp) on the same seeds: training ROC area 0.9963;
    // on 600 fresh wild seeds (30001-30300, 40001-40300) 0.9907, as for the 64-ray detector
    // with its own fit. Refitted again for the first threshold that clears a noisy pupil
    // (measureLevels), with the inside's level against the pupil's recent one added and the axis
    // ratio taken against the eye's own (StarburstConfig::eyeRatioMargin) once learnt: 149,965
    // answers, training ROC area 0.9969, halves 0.9965 / 0.9970 on each other; on the 600 fresh
    // wild seeds 0.9923 (0.9901 with neither input, 0.9910 with the level alone; the raw ratio's
    // larger weight put 13 % of the right answers on wild seed 63, an eye seen from the side,
    // under the gate). A lash clump or a shadow on the lid, answered while the pupil was under
    // it, fits as well as a pupil but is brighter (wild seed 40056: inside 93, the pupil's 40).
    // The product's own weight is now about nil: what it multiplies is in the other inputs.
    // Also tried and left out (64 rays): the inside's spread (upper quartile less median, over
    // the contrast), the contrast over the surround, the whole outline's support and whether a
    // darker blob inside lost to the answer: on 30001-30300 0.9887 against 0.9884 without them.
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
