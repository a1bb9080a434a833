#pragma once
// The naive baseline: threshold the frame a little above its darkest pixels, take the largest
// connected blob, fit an ellipse to its outline. Confidence is the blob's fill of its ellipse.
// No glint handling, no eyelid or lash rejection: it is here to be beaten, on the same clips and
// through the same interface as the real detector (`--detector blob`).
#include "pupil/pupil_detector.hpp"

namespace gt::eyetrack {

class BlobDetector final : public PupilDetector {
public:
    [[nodiscard]] PupilResult detect(const cv::Mat& grey, double tMs) override;
    using PupilDetector::detect;
    void reset() override {}
    [[nodiscard]] std::string name() const override { return "blob"; }

private:
    cv::Mat mMask, mLabels, mStats, mCentroids;
};

} // namespace gt::eyetrack
