#pragma once
// Head-mounted displays for the HMD path: per-eye panel size, field of view as the four tangents
// of the left eye (the right eye mirrors it), inter-pupillary distance, refresh rate, and the
// lens: a radial polynomial with per-channel scales for chromatic aberration. Each value carries
// its source; where a vendor publishes none it says what it was fitted to.
#include <array>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "foveation/contrast_sensitivity.hpp"

namespace gt::display {

// Barrel pre-distortion, applied by pass `lens` to each eye's finished image so the headset's
// pincushion lens shows it undistorted. A display pixel at normalised position q (0..1 across
// the eye's half of the panel) shows the rendered image at
//   src = c + (q - c) * f(r) * chroma[channel],   r = |(q - c) * (aspect, 1)| / rMax,
//   f(r) = (1 + k1 r^2 + k2 r^4) / (1 + k1 + k2),
// c the lens centre (where the optical axis meets the image), rMax the distance from c to the
// farthest corner of the eye's image (so f(1) = 1 and the rendered image is used to its edge),
// and aspect = width / height (r is measured in pixel-square units). f < 1 inside: the centre of
// the panel shows a smaller part of the image, magnified — barrel distortion.
struct LensModel {
    float k1 = 0.0f;
    float k2 = 0.0f;
    glm::vec3 chroma{1.0f}; // radial scale per channel (red, green, blue); green = 1
    [[nodiscard]] float f(float r) const noexcept;
    // Where display point q (normalised) samples the rendered image, for `channel` 0..2.
    [[nodiscard]] glm::vec2 sourceOf(glm::vec2 q, glm::vec2 centre, float aspect,
                                     int channel) const noexcept;
    // The inverse for green: the display point showing rendered point `src` (Newton, 8 steps).
    [[nodiscard]] glm::vec2 displayOf(glm::vec2 src, glm::vec2 centre, float aspect) const noexcept;
    // Local magnification |d src / d q| along the radius (the display-space density factor).
    [[nodiscard]] float radialScale(float r) const noexcept;
};

struct HmdProfile {
    std::string name;
    uint32_t eyeWidth = 0, eyeHeight = 0; // pixels per eye
    double refreshHz = 90.0;
    // Left eye, as tangents of the angles from the optical axis (left and down negative); the
    // nasal side (right, for the left eye) is the narrower one.
    float tanLeft = -1.0f, tanRight = 1.0f, tanUp = 1.0f, tanDown = -1.0f;
    float ipdM = 0.064f;
    LensModel lens;
    // The display its point sets are built for: pixels per eye and the viewing distance v of
    // thesis eq. (1) in eye-image widths.
    foveation::DisplayProfile pointSetProfile =
        foveation::displayProfile(foveation::DisplayModel::Fove);
    std::vector<std::string> sources; // where each value comes from
};

// The headsets gazetrace knows: the thesis's FOVE and two of its time, then eye-tracked
// headsets on sale since, whose point sets take v from their field of view (fovDisplayProfile).
enum class HmdModel {
    Fove,
    Vive,
    RiftCv1,
    ViveProEye,
    QuestPro,
    Psvr2,
    PimaxCrystal,
    VarjoXr4,
    VisionPro
};
inline constexpr std::array<HmdModel, 9> kHmdModels{
    HmdModel::Fove,         HmdModel::Vive,     HmdModel::RiftCv1,
    HmdModel::ViveProEye,   HmdModel::QuestPro, HmdModel::Psvr2,
    HmdModel::PimaxCrystal, HmdModel::VarjoXr4, HmdModel::VisionPro};
[[nodiscard]] HmdProfile hmdProfile(HmdModel model);

// A headset known only by its eye image and field of view (--hmd custom:...): `width` x
// `height` pixels per eye spanning `hfovDeg` x `vfovDeg` symmetrically about
// the optical axis, the published lens, and the point set of that field of view. Throws
// gt::ArgumentError for a size of 0 or a field of view outside (0, 180) degrees.
[[nodiscard]] HmdProfile customHmdProfile(std::string name, uint32_t width, uint32_t height,
                                          double hfovDeg, double vfovDeg, double refreshHz);

// The eye image's full horizontal field of view in degrees (temporal plus nasal half-angle).
[[nodiscard]] double horizontalFovDeg(const HmdProfile& p);
[[nodiscard]] double verticalFovDeg(const HmdProfile& p);
// Pixels per degree at the centre of the point set's display: thesis eq. (1) gives
// de/dd = 180 / (pi N v) degrees per pixel at d = 0, so ppd = pi N v / 180 (twice the display
// Nyquist fd of eq. (3)).
[[nodiscard]] double centrePixelsPerDegree(const HmdProfile& p);

// The eye's frustum tangents: left eye as stored, right eye mirrored about the nose.
struct EyeTangents {
    float left, right, up, down;
};
[[nodiscard]] EyeTangents eyeTangents(const HmdProfile& p, int eye); // eye 0 left, 1 right
// The lens centre of an eye in normalised image coordinates (0..1, y down): the optical axis.
[[nodiscard]] glm::vec2 lensCentre(const EyeTangents& t) noexcept;

} // namespace gt::display
