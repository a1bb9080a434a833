#pragma once
// Where a gaze lands in a view, once for every front end: a gaze given as angles lands on the
// desktop profile's physical screen and from there in a window on it, or through an HMD eye's
// own projection; screen pixels are moved into the window; the result is clamped to the image
// (a gaze off the image foveates its nearest edge).
#include <cstdint>

#include <glm/glm.hpp>

#include "gaze_input.hpp"
#include "view.hpp"

namespace gt::app {

// The gaze clamped to the pixels of a w x h image.
[[nodiscard]] glm::vec2 clampToImage(glm::vec2 px, uint32_t w, uint32_t h);

// Angles (yaw right, pitch up, degrees) on the desktop profile's screen, in the pixels of a
// window whose top-left corner lies at `windowOrigin` on that screen.
[[nodiscard]] glm::vec2 windowPixelOfAngles(glm::vec2 anglesDeg, glm::vec2 windowOrigin);

// Angles on a headless render of `view`: the desktop profile's render is a window centred on
// its screen; an HMD eye (fove, vive) rendered on its own maps them through the view's own
// projection. No flat rescaling of pixels between screens.
[[nodiscard]] glm::vec2 renderPixelOfAngles(glm::vec2 anglesDeg, bool desktop,
                                            const render::View& view);

// A reading of any gaze source in the pixels of a window at `windowOrigin` on the screen:
// angles land on the screen, screen pixels are moved into the window, window pixels (mouse,
// pixel traces) are used as they are.
[[nodiscard]] glm::vec2 windowPixelOf(const GazeReading& reading, glm::vec2 windowOrigin);

} // namespace gt::app
