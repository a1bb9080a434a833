#include "display/hmd_profile.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "core/error.hpp"

namespace gt::display {

float LensModel::f(float r) const noexcept {
    const float r2 = r * r;
    return (1.0f + k1 * r2 + k2 * r2 * r2) / (1.0f + k1 + k2);
}

float LensModel::radialScale(float r) const noexcept {
    // d(r f(r))/dr = f(r) + r f'(r)
    const float r2 = r * r;
    return (1.0f + 3.0f * k1 * r2 + 5.0f * k2 * r2 * r2) / (1.0f + k1 + k2);
}

namespace {
float rMax(glm::vec2 c, float aspect) {
    // The farthest corner of the unit square from c, in pixel-square units.
    const float dx = std::max(c.x, 1.0f - c.x) * aspect;
    const float dy = std::max(c.y, 1.0f - c.y);
    return std::sqrt(dx * dx + dy * dy);
}
} // namespace

glm::vec2 LensModel::sourceOf(glm::vec2 q, glm::vec2 c, float aspect, int channel) const noexcept {
    const glm::vec2 d = q - c;
    const float r = glm::length(d * glm::vec2(aspect, 1.0f)) / rMax(c, aspect);
    return c + d * f(r) * chroma[channel];
}

glm::vec2 LensModel::displayOf(glm::vec2 src, glm::vec2 c, float aspect) const noexcept {
    // Radial: solve s = q f(q) for q along the same direction.
    const glm::vec2 d = src - c;
    const float scale = glm::length(d * glm::vec2(aspect, 1.0f)) / rMax(c, aspect);
    if (scale <= 0.0f) return src;
    float r = scale;
    for (int i = 0; i < 8; ++i) {
        r -= (r * f(r) - scale) / radialScale(r);
    }
    return c + d * (r / scale);
}

namespace {
// The Oculus SDK 0.2 (2013) DK1 lens: K = (1.0, 0.22, 0.24), chromatic scales 0.996 (red) and
// 1.014 (blue) — the last distortion coefficients a vendor published. Current HMDs keep theirs in
// each device's firmware or calibration file (Monado's Vive and Rift drivers read them at run
// time), so every profile below uses this published lens as the model, scaled to each HMD's
// field of view through the normalised radius.
constexpr LensModel kPublishedLens{0.22f, 0.24f, {0.996f, 1.0f, 1.014f}};

// The left eye's field of view from its half-angles: temporal (left), nasal (right), and
// vertical (up and down alike), in degrees.
void setFov(HmdProfile& p, float temporalDeg, float nasalDeg, float verticalDeg) {
    p.tanLeft = -std::tan(glm::radians(temporalDeg));
    p.tanRight = std::tan(glm::radians(nasalDeg));
    p.tanUp = std::tan(glm::radians(verticalDeg));
    p.tanDown = -p.tanUp;
}

// A point set whose v comes from the eye's horizontal field of view (v = 1 / (2 tan(HFOV / 2)),
// fovDisplayProfile), not the fitted v of fove and vive.
void setFovPointSet(HmdProfile& p, double horizontalDeg) {
    p.pointSetProfile =
        foveation::fovDisplayProfile(p.name, p.eyeWidth, p.eyeHeight, horizontalDeg);
}

// A headset whose vendor states one horizontal field of view per eye: split evenly about the
// optical axis (no vendor publishes the split) and, where no vertical one is stated either,
// the vertical extent the panel's aspect gives at the same pixels per tangent (square pixels
// in the image plane). The point set follows the stated field.
void setSymmetricFov(HmdProfile& p, double horizontalDeg, double verticalDeg = 0.0) {
    setFovPointSet(p, horizontalDeg);
    const double tanH = std::tan(0.5 * horizontalDeg * std::numbers::pi / 180.0);
    const double tanV = verticalDeg > 0.0 ? std::tan(0.5 * verticalDeg * std::numbers::pi / 180.0)
                                          : tanH * p.eyeHeight / p.eyeWidth;
    p.tanLeft = static_cast<float>(-tanH);
    p.tanRight = static_cast<float>(tanH);
    p.tanUp = static_cast<float>(tanV);
    p.tanDown = -p.tanUp;
}

constexpr const char* kMeanIpd = "IPD: 64 mm, the adult mean (Dodgson 2004)";
constexpr const char* kScaledLens =
    "lens: Oculus SDK 0.2 DK1 coefficients scaled to the field of view (the vendor publishes "
    "none); approximate";
constexpr const char* kFovPointSet =
    "point set: v = 1 / (2 tan(HFOV / 2)) from the horizontal field of view";

// Eye-tracked headsets on sale after the thesis: pixels per eye, refresh (the highest the
// vendor lists) and field of view from the sources each names.
void setCurrentHeadset(HmdProfile& p, HmdModel model) {
    switch (model) {
    case HmdModel::ViveProEye:
        // HTC Vive Pro Eye: 2880x1600, 1440x1600 per eye, 90 Hz, 110 degrees (vendor).
        p = {"vive-pro-eye", 1440, 1600, 90.0};
        setSymmetricFov(p, 110.0);
        p.sources = {"resolution, refresh: HTC Vive Pro Eye specification (vendor)",
                     "FOV: 110 degrees (vendor), taken as each eye's horizontal field, split "
                     "evenly; vertical from the panel's aspect; approximate"};
        break;
    case HmdModel::QuestPro:
        // Meta Quest Pro: 1800x1920 per eye, 90 Hz, 106 x 96 degrees (vendor).
        p = {"quest-pro", 1800, 1920, 90.0};
        setSymmetricFov(p, 106.0, 96.0);
        p.sources = {"resolution, refresh, FOV (106 x 96 degrees): Meta Quest Pro technical "
                     "specifications (vendor)",
                     "FOV split evenly about the optical axis; approximate"};
        break;
    case HmdModel::Psvr2:
        // Sony PlayStation VR2: 2000x2040 per eye, 90/120 Hz, about 110 degrees (vendor).
        p = {"psvr2", 2000, 2040, 120.0};
        setSymmetricFov(p, 110.0);
        p.sources = {"resolution, refresh (90 or 120 Hz): PlayStation VR2 specification "
                     "(PlayStation Blog, 2022)",
                     "FOV: approximately 110 degrees (vendor), taken as each eye's horizontal "
                     "field, split evenly; vertical from the panel's aspect; approximate"};
        break;
    case HmdModel::PimaxCrystal:
        // Pimax Crystal: 2880x2880 per eye, 72/90/120 Hz (vendor). Pimax quotes a diagonal
        // field of view; the frustum its runtime reports (hmdq, Pimax Crystal at 120 Hz) is
        // left -1.264092, right 0.889501, up and down 1.274264: 93.3 x 103.8 degrees.
        p = {"pimax-crystal", 2880, 2880, 120.0};
        p.tanLeft = -1.264092f;
        p.tanRight = 0.889501f;
        p.tanUp = 1.274264f;
        p.tanDown = -1.274264f;
        setFovPointSet(p, horizontalFovDeg(p));
        p.sources = {"resolution, refresh: Pimax Crystal specification (vendor)",
                     "FOV: the runtime's frustum as recorded by hmdq (HMD Geometry Database, "
                     "risa2000.github.io/hmdgdb, PimaxCrystal_Native_R120); the vendor's "
                     "125-140 degrees are diagonal"};
        break;
    case HmdModel::VarjoXr4:
        // Varjo XR-4: 3840x3744 per eye, 90 Hz, 120 x 105 degrees (vendor).
        p = {"varjo-xr4", 3840, 3744, 90.0};
        setSymmetricFov(p, 120.0, 105.0);
        p.sources = {"resolution, refresh, FOV (120 x 105 degrees): Varjo XR-4 specification "
                     "(vendor, 2023)",
                     "FOV split evenly about the optical axis; approximate",
                     "the vendor's 51 pixels per degree at the centre come from its lens's "
                     "variable magnification; the pinhole model here spreads the pixels evenly "
                     "in tangent"};
        break;
    case HmdModel::VisionPro:
        // Apple Vision Pro class: 23 million pixels (vendor), about 3660x3200 per eye and about
        // 100 degrees horizontally (iFixit's teardown estimates), 90/96/100 Hz (vendor).
        p = {"vision-pro", 3660, 3200, 100.0};
        setSymmetricFov(p, 100.0);
        p.sources = {"resolution: 3660x3200 per eye, iFixit teardown estimate (Apple states 23 "
                     "million pixels in all); approximate",
                     "refresh: 90, 96 or 100 Hz (vendor)",
                     "FOV: about 100 degrees horizontally (iFixit estimate), split evenly; "
                     "vertical from the panel's aspect; approximate"};
        break;
    case HmdModel::Fove:
    case HmdModel::Vive:
    case HmdModel::RiftCv1:
        return; // the thesis's time: hmdProfile sets them
    }
    p.ipdM = 0.064f;
    p.lens = kPublishedLens;
    p.sources.emplace_back(kMeanIpd);
    p.sources.emplace_back(kScaledLens);
    p.sources.emplace_back(kFovPointSet);
}
} // namespace

HmdProfile hmdProfile(HmdModel model) {
    HmdProfile p;
    p.lens = kPublishedLens;
    switch (model) {
    case HmdModel::Fove:
        // FOVE 0: one 2560x1440 panel, 1280x1440 per eye (vendor specification); about 100
        // degrees horizontally (vendor); 70 Hz panel (vendor), run at 90 Hz in the thesis's
        // experiments. The tangents split 100 degrees 52/48 temporal/nasal (fitted: the lens
        // centre sits 2 % towards the nose, as in the other two).
        p.eyeWidth = 1280;
        p.eyeHeight = 1440;
        p.refreshHz = 90.0;
        setFov(p, 52.0f, 48.0f, 53.0f);
        p.ipdM = 0.064f;
        p.name = "fove";
        p.pointSetProfile = foveation::displayProfile(foveation::DisplayModel::Fove);
        p.sources = {"resolution, FOV: FOVE 0 specification (vendor)",
                     "refresh: 90 Hz as in the thesis's experiments",
                     "IPD: 64 mm, the adult mean (Dodgson 2004)",
                     "lens: Oculus SDK 0.2 DK1 coefficients (no vendor publishes FOVE's); "
                     "approximate"};
        break;
    case HmdModel::Vive:
        // HTC Vive: 2160x1200 panel, 1080x1200 per eye, 90 Hz, about 110 degrees (vendor).
        p.eyeWidth = 1080;
        p.eyeHeight = 1200;
        p.refreshHz = 90.0;
        setFov(p, 56.0f, 50.0f, 55.0f);
        p.ipdM = 0.064f;
        p.name = "vive";
        p.pointSetProfile = foveation::displayProfile(foveation::DisplayModel::Vive);
        p.sources = {"resolution, refresh, FOV: HTC Vive specification (vendor)",
                     "IPD: 64 mm, the adult mean (Dodgson 2004)",
                     "lens: Oculus SDK 0.2 DK1 coefficients (each Vive stores its own in its "
                     "configuration; none are published); approximate"};
        break;
    case HmdModel::RiftCv1:
        // Oculus Rift CV1: 2160x1200 panel, 1080x1200 per eye, 90 Hz (vendor); about 94 degrees
        // horizontally per eye, 93 vertically (published teardown measurements, approximate).
        p.eyeWidth = 1080;
        p.eyeHeight = 1200;
        p.refreshHz = 90.0;
        setFov(p, 49.0f, 45.0f, 46.5f);
        p.ipdM = 0.0635f;
        p.name = "rift-cv1";
        p.pointSetProfile = foveation::displayProfile(foveation::DisplayModel::Vive);
        p.sources = {"resolution, refresh: Oculus Rift CV1 specification (vendor)",
                     "FOV: about 94 x 93 degrees per eye (measured by reviewers; approximate)",
                     "IPD: 63.5 mm, the Rift's default",
                     "lens: Oculus SDK 0.2 DK1 coefficients (CV1's spline is in firmware and "
                     "unpublished); approximate",
                     "point set: the vive profile's (same 1080x1200 panel per eye)"};
        break;
    case HmdModel::ViveProEye:
    case HmdModel::QuestPro:
    case HmdModel::Psvr2:
    case HmdModel::PimaxCrystal:
    case HmdModel::VarjoXr4:
    case HmdModel::VisionPro:
        setCurrentHeadset(p, model);
        break;
    }
    return p;
}

HmdProfile customHmdProfile(std::string name, uint32_t width, uint32_t height, double hfovDeg,
                            double vfovDeg, double refreshHz) {
    if (!(vfovDeg > 0.0 && vfovDeg < 180.0)) {
        throw ArgumentError("a vertical field of view of " + std::to_string(vfovDeg) +
                            " degrees (expected more than 0 and less than 180)");
    }
    HmdProfile p{std::move(name), width, height, refreshHz};
    setSymmetricFov(p, hfovDeg, vfovDeg);
    p.lens = kPublishedLens;
    p.sources = {"resolution, FOV, refresh: as given on the command line; FOV symmetric about "
                 "the optical axis",
                 kMeanIpd, kScaledLens, kFovPointSet};
    return p;
}

double horizontalFovDeg(const HmdProfile& p) {
    return (std::atan(static_cast<double>(p.tanRight)) -
            std::atan(static_cast<double>(p.tanLeft))) *
           180.0 / std::numbers::pi;
}

double verticalFovDeg(const HmdProfile& p) {
    return (std::atan(static_cast<double>(p.tanUp)) - std::atan(static_cast<double>(p.tanDown))) *
           180.0 / std::numbers::pi;
}

double centrePixelsPerDegree(const HmdProfile& p) {
    const foveation::DisplayProfile& d = p.pointSetProfile;
    return std::numbers::pi * d.width * d.viewingDistance / 180.0;
}

EyeTangents eyeTangents(const HmdProfile& p, int eye) {
    if (eye == 0) return {p.tanLeft, p.tanRight, p.tanUp, p.tanDown};
    return {-p.tanRight, -p.tanLeft, p.tanUp, p.tanDown};
}

glm::vec2 lensCentre(const EyeTangents& t) noexcept {
    return {-t.left / (t.right - t.left), t.up / (t.up - t.down)};
}

} // namespace gt::display
