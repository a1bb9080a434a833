#pragma once
// What every pupil detector is to the rest of the tracker: a grey frame and its time in, the pupil
// (sub-pixel centre, ellipse, confidence) out. The eye pipeline (gaze/eye_pipeline.hpp), the
// calibration, `track`, `calibrate` and `eyescore` all work through this interface, so a detector
// is chosen by name (`--detector`) and compared on the same clips.
//  - starburst (default; pupil/starburst_detector.hpp): centre-surround candidates, rays to the
//    boundary, RANSAC ellipse, a confidence from outline, edge sharpness and a filled interior;
//  - blob (pupil/blob_detector.hpp): threshold at the darkest percentile and take the largest
//    blob — the naive baseline, kept to measure against.
// Confidence is in [0, 1]; `found` is the detector's own cut. Detectors keep state between frames
// (a temporal prior), so frames are given in order; reset() forgets it (a new recording).
#include <memory>
#include <string>

#include <opencv2/core.hpp>

namespace gt::eyetrack {

struct PupilResult {
    bool found = false;
    cv::RotatedRect ellipse; // centre, full axes, angle (OpenCV convention)
    double confidence = 0.0;
    [[nodiscard]] cv::Point2d centre() const { return {ellipse.center.x, ellipse.center.y}; }
    [[nodiscard]] double semiMajor() const;
    [[nodiscard]] double semiMinor() const;
    [[nodiscard]] double majorAngleDeg() const; // direction of the major axis, [0, 180)
};

class PupilDetector {
public:
    virtual ~PupilDetector() = default;
    PupilDetector() = default;
    PupilDetector(const PupilDetector&) = delete;
    PupilDetector& operator=(const PupilDetector&) = delete;

    // grey: CV_8UC1 (throws EyetrackError otherwise); tMs: the frame's time stamp.
    [[nodiscard]] virtual PupilResult detect(const cv::Mat& grey, double tMs) = 0;
    // For still images and tests: frames one 120 Hz period apart.
    [[nodiscard]] PupilResult detect(const cv::Mat& grey) { return detect(grey, mNextMs += 8.3); }
    virtual void reset() = 0;
    [[nodiscard]] virtual std::string name() const = 0;

private:
    double mNextMs = 0.0;
};

// The pupil detectors gazetrace has.
enum class PupilDetectorKind {
    Starburst, // rays from a dark seed to the pupil's edge, then an ellipse fit
    Blob,      // the largest dark blob's outline, then an ellipse fit: the naive baseline
};

[[nodiscard]] std::unique_ptr<PupilDetector> makePupilDetector(PupilDetectorKind kind);

} // namespace gt::eyetrack
