#include "gaze_bounds.hpp"

#include <algorithm>
#include <cmath>

#include "core/log.hpp"
#include "foveation/gaze_trace.hpp"

namespace gt::app {

bool gazeOutside(glm::vec2 px, uint32_t width, uint32_t height) noexcept {
    return px.x < 0.0f || px.y < 0.0f || px.x >= static_cast<float>(width) ||
           px.y >= static_cast<float>(height);
}

std::string clampedGazeMessage(const std::string& subject, uint32_t width, uint32_t height,
                               const std::string& area) {
    return subject + " outside the " + std::to_string(width) + "x" + std::to_string(height) + " " +
           area + "; the gaze is clamped to its edge there";
}

void warnOffScreen(const foveation::GazeTrace& trace, const std::string& file, uint32_t width,
                   uint32_t height) {
    const auto& samples = trace.samples();
    const auto outside = std::count_if(samples.begin(), samples.end(), [&](const auto& s) {
        return gazeOutside(s.position, width, height);
    });
    if (outside == 0) {
        return;
    }
    log::warn(clampedGazeMessage(file + ": " + std::to_string(outside) + " of " +
                                     std::to_string(samples.size()) + " gaze samples lie",
                                 width, height, "screen"));
}

bool OffScreenGazeWarning::check(glm::vec2 px, uint32_t width, uint32_t height) {
    if (mWarned || !gazeOutside(px, width, height)) {
        return false;
    }
    mWarned = true;
    const std::string at =
        "(" + std::to_string(std::lround(px.x)) + ", " + std::to_string(std::lround(px.y)) + ")";
    log::warn(clampedGazeMessage("gaze " + mSource + ": the gaze " + at + " lies", width, height,
                                 "window") +
              " (said once)");
    return true;
}

} // namespace gt::app
