#include "display/hmd_profile.hpp"

#include <algorithm>
#include <cmath>

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
// time), so the three profiles below use this published lens as the model, scaled to each
// HMD's field of view through the normalised radius.
constexpr LensModel kPublishedLens{0.22f, 0.24f, {0.996f, 1.0f, 1.014f}};

// The left eye's field of view from its half-angles: temporal (left), nasal (right), and
// vertical (up and down alike), in degrees.
void setFov(HmdProfile& p, float temporalDeg, float nasalDeg, float verticalDeg) {
    p.tanLeft = -std::tan(glm::radians(temporalDeg));
    p.tanRight = std::tan(glm::radians(nasalDeg));
    p.tanUp = std::tan(glm::radians(verticalDeg));
    p.tanDown = -p.tanUp;
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
    }
    return p;
}

EyeTangents eyeTangents(const HmdProfile& p, int eye) {
    if (eye == 0) return {p.tanLeft, p.tanRight, p.tanUp, p.tanDown};
    return {-p.tanRight, -p.tanLeft, p.tanUp, p.tanDown};
}

glm::vec2 lensCentre(const EyeTangents& t) noexcept {
    return {-t.left / (t.right - t.left), t.up / (t.up - t.down)};
}

} // namespace gt::display
