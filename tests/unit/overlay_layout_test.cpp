// The demo's overlay panel at the default 640 x 360 window: inside the window, off the circle of
// fine detail around the gaze, in a font scale that keeps one-pixel glyphs (the decimal point).
#include <cmath>

#include <gtest/gtest.h>

#include "overlay_layout.hpp"

namespace gt::app {
namespace {

// The desktop screen (51 cm, 1920 pixels, seen from 59 cm): 38.8 pixels per degree.
const float kPpd = static_cast<float>(59.0 * std::tan(M_PI / 180.0) * 1920.0 / 51.0);

void expectInside(const OverlayLayout& l, glm::vec2 window) {
    EXPECT_GE(l.position.x, 0.0f);
    EXPECT_GE(l.position.y, 0.0f);
    EXPECT_LE(l.position.x + l.maxSize.x, window.x);
    EXPECT_LE(l.position.y + l.maxSize.y, window.y);
}

TEST(OverlayLayout, FitsTheDefaultWindowOffTheFovea) {
    const glm::vec2 window(640.0f, 360.0f);
    const float radius = 0.5f * kFineDetailDiameterDeg * kPpd; // 97 pixels
    for (const glm::vec2 gaze : {glm::vec2(320, 180), glm::vec2(100, 60), glm::vec2(600, 340),
                                 glm::vec2(320, 20), glm::vec2(20, 180), glm::vec2(500, 100)}) {
        const OverlayLayout l = overlayLayout(window, gaze, kPpd);
        expectInside(l, window);
        EXPECT_GT(distanceToPanel(l, gaze), radius) << gaze.x << "," << gaze.y;
        // Small: at most 15 % of the window.
        EXPECT_LE(l.maxSize.x * l.maxSize.y, 0.15f * window.x * window.y);
    }
}

TEST(OverlayLayout, TakesTheCornerAwayFromTheGazeAndStaysWhileItClears) {
    const glm::vec2 window(640.0f, 360.0f);
    EXPECT_EQ(overlayLayout(window, {60, 40}, kPpd).corner, 3);   // gaze top-left: bottom-right
    EXPECT_EQ(overlayLayout(window, {600, 330}, kPpd).corner, 0); // gaze bottom-right: top-left
    // The gaze moves a little past the middle: the panel stays where it is.
    EXPECT_EQ(overlayLayout(window, {330, 185}, kPpd, 0).corner, 0);
    // The gaze comes near the panel's corner: it moves away.
    EXPECT_EQ(overlayLayout(window, {40, 30}, kPpd, 0).corner, 3);
}

TEST(OverlayLayout, FontScaleKeepsOnePixelGlyphs) {
    for (const glm::vec2 window : {glm::vec2(320, 180), glm::vec2(640, 360), glm::vec2(1280, 720),
                                   glm::vec2(1920, 1080), glm::vec2(3840, 2160)}) {
        const float s = overlayLayout(window, 0.5f * window, kPpd).fontScale;
        EXPECT_GE(s, 1.0f) << window.x;
        EXPECT_EQ(s, std::floor(s)) << window.x;
    }
    EXPECT_EQ(overlayLayout({640, 360}, {320, 180}, kPpd).fontScale, 1.0f);
    EXPECT_EQ(overlayLayout({1920, 1080}, {960, 540}, kPpd).fontScale, 2.0f);
}

TEST(OverlayLayout, NumbersKeepTheirDecimalPoint) {
    EXPECT_EQ(frameRateText(312.5), "3.2 fps  312.5 ms/frame");
    EXPECT_EQ(frameRateText(0.0), "0.0 fps  0.0 ms/frame");
    const std::string latency = latencyText(278.94);
    EXPECT_NE(latency.find("278.9 ms"), std::string::npos) << latency;
    // Named for what it measures: not gaze-to-photon.
    EXPECT_EQ(latency.find("photon"), std::string::npos) << latency;
}

} // namespace
} // namespace gt::app
