#pragma once
// What the starburst detector has learnt of this eye from its confident answers: the pupil's
// recent size, inside level and contrast (PuReST's size consistency, Santini, Fuhl & Kasneci
// 2018), the axis ratio its whole pupil shows, and the shape its pupils have at each place
// (pupil_shape_model.hpp).
#include <opencv2/core.hpp>

#include "pupil/pupil_detector.hpp"
#include "pupil/pupil_shape_model.hpp"

namespace gt::eyetrack::starburst {

// What the detector measured on the answer it gave, for the priors to learn from.
struct PickedAnswer {
    PupilResult result;       // its confidence the detector's own, the size prior applied
    double sizeFactor = 1.0;  // the size prior's factor in it
    double shapeFactor = 1.0; // the axis-ratio ramp's factor in it
    double supportAll = 0.0;  // the whole outline's support
    double interior = 0.0;    // median grey level inside
    double outside = -1.0;    // just outside the outline (-1: unknown)
    bool uniform = false;     // a uniformly dark inside, no darker blob in it
};

struct PupilPriors {
    double recentRadius = 0.0;   // running pupil size from confident frames, 0 = unknown
    double recentMinor = 0.0;    // its minor semi-axis, learnt alike
    double recentLevel = -1.0;   // the pupil's inside grey level, learnt alike (-1 = unknown)
    double recentContrast = 0.0; // and the step from it to just outside its outline
    int framesSinceSize = 0;
    double eyeRatio = 0.0; // running axis ratio of the whole pupil (0 = unknown)
    PupilShapeModel shape;

    void reset();
    // Learns from a frame's answer (eyeRatioMargin: StarburstConfig's, 0 = the eye's axis ratio
    // is not learnt).
    void learn(const PickedAnswer& answer, double eyeRatioMargin);
};

} // namespace gt::eyetrack::starburst
