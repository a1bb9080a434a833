#pragma once
// A gaze outside the picture is clamped to its edge by every front end (the renderer samples
// around a pixel of the image). Say so, once, rather than render a fovea stuck in a corner in
// silence: it usually means a trace recorded for another screen (the FOVE's 1280 x 1440 pixels
// in a smaller window), or a mouse outside the window.
#include <cstdint>
#include <string>

#include <glm/glm.hpp>

namespace gt::foveation {
class GazeTrace;
}

namespace gt::app {

// Whether `px` lies outside a `width` x `height` picture (pixels, origin top-left).
[[nodiscard]] bool gazeOutside(glm::vec2 px, uint32_t width, uint32_t height) noexcept;

// "SUBJECT outside the WxH AREA; the gaze is clamped to its edge there": the one wording of the
// warning, for a whole trace (`render`) and for a live gaze (`demo`).
[[nodiscard]] std::string clampedGazeMessage(const std::string& subject, uint32_t width,
                                             uint32_t height, const std::string& area);

// A trace's samples outside the screen, counted and reported in one warning (none if all lie
// inside).
void warnOffScreen(const foveation::GazeTrace& trace, const std::string& file, uint32_t width,
                   uint32_t height);

// A live gaze: warns the first time it lies outside the window, and never again.
class OffScreenGazeWarning {
public:
    explicit OffScreenGazeWarning(std::string source) : mSource(std::move(source)) {}
    // True when this call warned.
    bool check(glm::vec2 px, uint32_t width, uint32_t height);

private:
    std::string mSource;
    bool mWarned = false;
};

} // namespace gt::app
