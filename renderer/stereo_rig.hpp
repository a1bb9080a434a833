#pragma once
// The HMD path's two views: each eye at half the inter-pupillary distance from the head, looking
// along the head's axis through its own off-axis frustum (the profile's tangents, mirrored for
// the right eye), with its lens. The gaze is one direction plus a vergence distance: the point
// the eyes converge on is projected through each eye's own frustum, so the two gaze pixels
// differ by the disparity of that point (and by the frusta's asymmetry).
#include <array>
#include <optional>

#include <glm/glm.hpp>

#include "display/hmd_profile.hpp"
#include "view.hpp"

namespace gt::render {

// Pixel <-> direction through a frustum given by tangents; directions in the eye's frame
// (x right, y up, z forward), pixels with origin top-left and centres at integers + 0.5 edges.
[[nodiscard]] glm::vec2 pixelOfDirection(glm::vec3 dir, const display::EyeTangents& t,
                                         uint32_t width, uint32_t height);
[[nodiscard]] glm::vec3 directionOfPixel(glm::vec2 pixel, const display::EyeTangents& t,
                                         uint32_t width, uint32_t height);
// Gaze angles (degrees; yaw right, pitch up, as the eye tracker's calibration gives them) to a
// direction in the eye's frame, and back.
[[nodiscard]] glm::vec3 directionOfAngles(glm::vec2 yawPitchDeg);
[[nodiscard]] glm::vec2 anglesOfDirection(glm::vec3 dir);

struct StereoGaze {
    glm::vec3 direction{0.0f, 0.0f, 1.0f}; // in the head's frame (x right, y up, z forward)
    std::optional<float> vergenceM;        // distance to the fixation point; empty: infinity
    // Two tracked eyes: each eye's own direction (its frame is the head's, moved by half the
    // IPD), which replaces `direction` and `vergenceM` for that eye.
    std::optional<glm::vec3> eyeDirection[2];
    bool saccade = false;
};

class StereoRig {
public:
    StereoRig(display::HmdProfile profile, bool distortion)
        : mProfile(std::move(profile)), mDistortion(distortion) {}
    [[nodiscard]] const display::HmdProfile& profile() const noexcept { return mProfile; }
    // The views "left" and "right" for the head pose `head` (its forward and up; yfov unused),
    // both with `method` and `post` (the lens is added when distortion is on).
    [[nodiscard]] std::array<View, 2> views(const scene::Camera& head, const StereoGaze& gaze,
                                            FoveationMethod& method, const PostSettings& post,
                                            float exposure) const;
    // The head-frame gaze direction of a pixel in the left eye's image (a trace recorded for
    // the eye image, or the mouse over the left half of the window).
    [[nodiscard]] glm::vec3 directionOfLeftPixel(glm::vec2 pixel) const;

private:
    display::HmdProfile mProfile;
    bool mDistortion;
};

} // namespace gt::render
