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
    // with its own fit. Also tried and left out (64 rays): the inside's spread (upper quartile
    // less median, over the contrast), the contrast over the surround, the whole outline's
    // support and whether a darker blob inside lost to the answer: on 30001-30300 0.9887
    // against 0.9884 without them.
    constexpr double kBias = -17.390;
    constexpr double kLogConfidence = 0.251;
    constexpr double kVisibleSupport = 4.520;
    constexpr double kFill = 7.000;
    constexpr double kAxisRatio = 6.590;
    constexpr double kLogSizeFactor = 0.666;
    constexpr double kScore = 4.652;
    constexpr double kRivalRatio = -0.725;   // rival's score over the answer's, at most 2
    constexpr double kLastDistance = -1.106; // in semi-major axes, at most 3
    constexpr double kNoLast = -1.263;
    constexpr double kSizeKnown = 1.522;
    const double rival = e.score > 0.0 ? std::min(2.0, e.rivalScore / e.score) : 0.0;
    const bool noLast = e.lastDistance < 0.0;
    const double last = noLast ? 0.0 : std::min(3.0, e.lastDistance / std::max(1.0, e.semiMajor));
    const double z = kBias + kLogConfidence * std::log(std::max(1e-3, e.confidence)) +
                     kVisibleSupport * e.visibleSupport + kFill * e.fill +
                     kAxisRatio * e.axisRatio +
                     kLogSizeFactor * std::log(std::max(1e-3, e.sizeFactor)) + kScore * e.score +
                     kRivalRatio * rival + kLastDistance * last + (noLast ? kNoLast : 0.0) +
                     (e.sizeKnown ? kSizeKnown : 0.0);
    return 1.0 / (1.0 + std::exp(-z));
}

} // namespace gt::eyetrack
