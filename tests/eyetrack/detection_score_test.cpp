// Scoring a detector: detection rate, ROC area and the gate's rates on hand-made records.
#include <gtest/gtest.h>

#include "score/detection_score.hpp"

using namespace gt::eyetrack;

TEST(DetectionScore, RocAreaAndGate) {
    std::vector<DetectionRecord> r;
    // Right answers with confidence 0.9, 0.8, 0.7; wrong ones 0.75, 0.3, and one on a hidden
    // pupil at 0.2; one visible frame with no answer.
    for (const double c : {0.9, 0.8, 0.7})
        r.push_back({true, true, 1.0, c});
    r.push_back({true, true, 12.0, 0.75});
    r.push_back({true, true, 6.0, 0.3});
    r.push_back({false, true, 0.5, 0.2});
    r.push_back({true, false, 0.0, 0.0});
    const DetectionScore s = scoreDetections(r, 5.0);
    EXPECT_EQ(s.visible, 6);
    EXPECT_EQ(s.withinRadius, 3);
    EXPECT_DOUBLE_EQ(s.detectionRate, 0.5);
    EXPECT_EQ(s.right, 3);
    EXPECT_EQ(s.wrong, 3);
    EXPECT_EQ(s.wrongHidden, 1);
    // Pairs (right, wrong) ordered right: 3 x 3 = 9, all but (0.7, 0.75): 8/9.
    EXPECT_NEAR(s.rocAuc, 8.0 / 9.0, 1e-12);
    const ThresholdRates g = ratesAt(r, 0.72, 5.0);
    EXPECT_NEAR(g.wrongRejected, 2.0 / 3.0, 1e-12);
    EXPECT_NEAR(g.rightKept, 2.0 / 3.0, 1e-12);
    // Ties count half.
    const DetectionScore tie = scoreDetections({{true, true, 1.0, 0.5}, {true, true, 9.0, 0.5}});
    EXPECT_DOUBLE_EQ(tie.rocAuc, 0.5);
}
