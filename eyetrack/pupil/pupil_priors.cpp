#include "pupil/pupil_priors.hpp"

#include <algorithm>

namespace gt::eyetrack::starburst {

namespace {

// The running means of the priors: a tenth of each new value, or the value itself when nothing
// was known (`known` false).
void runningMean(double& mean, double value, bool known) {
    mean = known ? 0.9 * mean + 0.1 * value : value;
}

} // namespace

void PupilPriors::reset() {
    recentRadius = 0.0;
    recentMinor = 0.0;
    recentLevel = -1.0;
    recentContrast = 0.0;
    framesSinceSize = 0;
    eyeRatio = 0.0;
    shape.reset();
}

void PupilPriors::learn(const PickedAnswer& answer, double eyeRatioMargin) {
    const PupilResult& best = answer.result;
    ++framesSinceSize;
    // The size prior learns only from a uniformly dark inside (PickedAnswer::uniform): an iris
    // with its pupil in it (picked while the pupil was hard to see) must not teach it the iris's
    // size, or the pupil would be held too small to be the pupil from then on. It learns from the
    // evidence, the size prior's own factor left out: with it, a pupil that shrank or grew by a
    // third while its confidence was low (a blink, a lid) would be held at its old size, its right
    // answers scored under the gate, and the prior would never catch up.
    const double evidence = best.confidence / std::max(1e-6, answer.sizeFactor);
    if (evidence >= 0.75 && answer.uniform) {
        runningMean(recentRadius, best.semiMajor(), recentRadius > 0.0);
        runningMean(recentMinor, best.semiMinor(), recentMinor > 0.0);
        if (answer.outside >= 0.0) {
            runningMean(recentContrast, answer.outside - answer.interior, recentContrast > 0.0);
            runningMean(recentLevel, answer.interior, recentLevel >= 0.0);
        }
        framesSinceSize = 0;
    } else if (framesSinceSize > 300) {
        recentRadius = 0.0; // lost for long: forget the size
        recentMinor = 0.0;
        recentLevel = -1.0;
        recentContrast = 0.0;
    }
    // The eye's own pupil shape (StarburstConfig::eyeRatioMargin) is learnt only from a pupil
    // seen whole (nine-tenths of its outline supported: a sliver under the lid is flat because
    // it is covered, not because of the camera's angle), judged without the ramp's own factor
    // (or a flat eye's pupils could never teach it). Whole-pupil fits are 0.02-0.1 off the true
    // ratio (the ratio also changes as the eye turns), which the 0.1 margin absorbs.
    if (eyeRatioMargin > 0.0 && answer.uniform && answer.supportAll >= 0.9 &&
        evidence / std::max(1e-6, answer.shapeFactor) >= 0.75) {
        const double ratio = best.semiMinor() / std::max(1e-6, best.semiMajor());
        runningMean(eyeRatio, ratio, eyeRatio > 0.0);
        shape.add(best.ellipse);
    }
}

} // namespace gt::eyetrack::starburst
