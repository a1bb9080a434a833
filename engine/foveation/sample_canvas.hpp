#pragma once
// Where a point set lands on screen (thesis, 4.2): the set lives on a canvas twice the display's
// size and shifts with the gaze; the points that fall on screen, plus a margin, are traced. The
// passes that trace the points and those that rebuild the image from them share this placement.
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace gt::foveation {

inline constexpr float kSampleMargin = 10.0f; // pixels beyond the screen (thesis 4.2)

// Canvas -> screen offset for a gaze point, in whole pixels (the set shifts by the gaze).
[[nodiscard]] inline glm::vec2 gazeOffset(glm::vec2 gaze, uint32_t displayWidth,
                                          uint32_t displayHeight) {
    return {std::round(gaze.x) - static_cast<float>(displayWidth),
            std::round(gaze.y) - static_cast<float>(displayHeight)};
}

} // namespace gt::foveation
