#include "foveation/contrast_sensitivity.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>

#include "core/error.hpp"

namespace gt::foveation {

// Chosen so the `fove` point set reproduces the thesis's Table 1 (576,775 points; 72.86 % on
// screen with the gaze centred, 26.68 % in a corner, counting the 10-pixel sampling margin of
// section 4.2): v = 0.85 gives about 576,500 points, 71.3 % and 26.5 % (tests/unit/
// point_set_test.cpp). The thesis does not state v; 0.85 display widths means the 1280-pixel
// eye image spans about 61 degrees. The Vive, a similar HMD, uses the same value.
constexpr double kFoveViewingDistance = 0.85;

DisplayProfile displayProfile(DisplayModel model) {
    switch (model) {
    case DisplayModel::Fove:
        return {"fove", 1280, 1440, kFoveViewingDistance};
    case DisplayModel::Vive:
        return {"vive", 1080, 1200, kFoveViewingDistance};
    case DisplayModel::Desktop:
        break;
    }
    return {"desktop", 1920, 1080, 59.0 / 51.0};
}

DisplayProfile windowProfile(const DisplayProfile& screen, uint32_t width, uint32_t height) {
    if (width == 0 || height == 0) throw ArgumentError("a window of zero size");
    if (width == screen.width && height == screen.height) return screen;
    return {screen.name + "-" + std::to_string(width) + "x" + std::to_string(height), width, height,
            screen.viewingDistance * static_cast<double>(screen.width) / width};
}

DisplayProfile fovDisplayProfile(std::string name, uint32_t width, uint32_t height,
                                 double horizontalFovDeg) {
    if (width == 0 || height == 0) throw ArgumentError("a display of zero size");
    if (!(horizontalFovDeg > 0.0 && horizontalFovDeg < 180.0)) {
        throw ArgumentError("a horizontal field of view of " + std::to_string(horizontalFovDeg) +
                            " degrees (expected more than 0 and less than 180)");
    }
    const double halfRad = 0.5 * horizontalFovDeg * std::numbers::pi / 180.0;
    return {std::move(name), width, height, 1.0 / (2.0 * std::tan(halfRad))};
}

double ContrastSensitivity::eccentricityDeg(double distancePx, double displayWidthPx,
                                            double viewingDistance, double scale) {
    return scale * std::atan(distancePx / (displayWidthPx * viewingDistance)) * 180.0 /
           std::numbers::pi;
}

double ContrastSensitivity::cutoffFrequency(double e) const {
    return e2 * std::log(1.0 / ct0) / ((e + e2) * alpha);
}

double ContrastSensitivity::displayNyquist(double displayWidthPx, double viewingDistance) {
    return std::numbers::pi * displayWidthPx * viewingDistance / 360.0;
}

double ContrastSensitivity::spacing(double distancePx, const DisplayProfile& display,
                                    double scale) const {
    const double n = display.width;
    const double fd = displayNyquist(n, display.viewingDistance);
    const double fc =
        cutoffFrequency(eccentricityDeg(distancePx, n, display.viewingDistance, scale));
    return fd / std::min(fd, fc) - (1.0 - std::sqrt(1.0 / std::numbers::pi));
}

} // namespace gt::foveation
