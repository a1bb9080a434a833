#include "gaze_view.hpp"

#include "gaze_mapping.hpp"

namespace gt::app {

glm::vec2 clampToImage(glm::vec2 px, uint32_t w, uint32_t h) {
    const glm::vec2 lastPixel(static_cast<float>(w) - 1.0f, static_cast<float>(h) - 1.0f);
    return glm::clamp(px, glm::vec2(0.0f), lastPixel);
}

glm::vec2 windowPixelOfAngles(glm::vec2 anglesDeg, glm::vec2 windowOrigin) {
    const render::ScreenGeometry screen; // the desktop profile's
    return screen.pixelOfAngles(anglesDeg) - windowOrigin;
}

glm::vec2 renderPixelOfAngles(glm::vec2 anglesDeg, bool desktop, const render::View& view) {
    if (!desktop) return render::pixelOfAnglesInView(anglesDeg, view);
    return windowPixelOfAngles(anglesDeg, render::centredWindowOrigin(render::ScreenGeometry{},
                                                                      {view.width, view.height}));
}

glm::vec2 windowPixelOf(const GazeReading& reading, glm::vec2 windowOrigin) {
    if (reading.anglesDeg) return windowPixelOfAngles(*reading.anglesDeg, windowOrigin);
    return reading.windowPixels ? reading.screenPx : reading.screenPx - windowOrigin;
}

} // namespace gt::app
