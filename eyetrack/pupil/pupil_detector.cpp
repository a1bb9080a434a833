#include "pupil/pupil_detector.hpp"

#include <algorithm>
#include <cmath>

#include "error.hpp"
#include "pupil/blob_detector.hpp"
#include "pupil/starburst_detector.hpp"

namespace gt::eyetrack {

double PupilResult::semiMajor() const {
    return 0.5 * std::max(ellipse.size.width, ellipse.size.height);
}
double PupilResult::semiMinor() const {
    return 0.5 * std::min(ellipse.size.width, ellipse.size.height);
}
double PupilResult::majorAngleDeg() const {
    const double a =
        ellipse.size.width >= ellipse.size.height ? ellipse.angle : ellipse.angle + 90.0;
    return std::fmod(std::fmod(a, 180.0) + 180.0, 180.0);
}

std::unique_ptr<PupilDetector> makePupilDetector(PupilDetectorKind kind) {
    if (kind == PupilDetectorKind::Blob) {
        return std::make_unique<BlobDetector>();
    }
    return std::make_unique<StarburstDetector>();
}

} // namespace gt::eyetrack
