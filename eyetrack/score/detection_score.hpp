#pragma once
// Scoring a pupil detector against truth: detection within a radius on the frames where the pupil
// can be seen, and whether its confidence tells right answers from wrong ones.
//  - A frame's answer is "right" when at least half the pupil is visible and the reported centre
//    is within `radiusPx` of the truth; every other answer the detector gives (a wrong place, or a
//    pupil reported while the eye is shut) is "wrong". Frames with no answer at all (confidence 0)
//    are neither: there is nothing for a filter to reject.
//  - ROC area: the probability that a random right answer has a higher confidence than a random
//    wrong one (ties count half; Mann-Whitney U / (n_right n_wrong)).
//  - At a threshold: the share of wrong answers it rejects (confidence below) and of right ones it
//    keeps (at or above), as the gaze filter's gate does.
#include <vector>

namespace gt::eyetrack {

// A frame "shows the pupil" when at least this share of it is outside the lids (every score).
inline constexpr double kVisibleShare = 0.5;

struct DetectionRecord {
    bool visible = false;  // at least half the pupil shows
    bool answered = false; // the detector returned an ellipse (any confidence > 0)
    double errorPx = 0.0;  // centre error, when answered
    double confidence = 0.0;
};

struct ThresholdRates {
    double threshold = 0.0;
    double wrongRejected = 0.0; // share of wrong answers below the threshold
    double rightKept = 0.0;     // share of right answers at or above it
};

struct DetectionScore {
    int frames = 0;
    int visible = 0;
    int withinRadius = 0;       // visible frames answered within the radius
    double detectionRate = 0.0; // withinRadius / visible
    double medianErrorPx = 0.0; // over answered visible frames
    int right = 0, wrong = 0;
    int wrongHidden = 0; // wrong answers on frames where the pupil is (mostly) hidden
    double rocAuc = 0.0; // 0 when there are no right or no wrong answers
};

[[nodiscard]] DetectionScore scoreDetections(const std::vector<DetectionRecord>& records,
                                             double radiusPx = 5.0);
[[nodiscard]] ThresholdRates ratesAt(const std::vector<DetectionRecord>& records, double threshold,
                                     double radiusPx = 5.0);
[[nodiscard]] bool isRight(const DetectionRecord& r, double radiusPx);

} // namespace gt::eyetrack
