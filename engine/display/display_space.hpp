#pragma once
// Sample density on the HMD's panel, after the lens. The perceptual point set (thesis, 4.1) is
// designed for a display's pixels; in an HMD the pixels are the panel's, and the eye's rendered
// image is an intermediate that the lens pass resamples (hmd_profile.hpp: a panel point q shows
// the image at src(q) = c + (q - c) f(r)). Laying the set in the image puts its density where the
// image's pixels are; laying it on the panel — centred where the eye looks on the panel, that is
// displayOf(gaze) — and carrying each point through src() puts it where the panel's pixels are.
// Barrel pre-distortion magnifies the centre (f < 1 there): the panel's centre shows a smaller part
// of the image, so laid on the panel the same set crowds the image's centre and thins its edges.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "display/hmd_profile.hpp"
#include "foveation/point_set.hpp"

namespace gt::display {

// The points of `set` shifted so its centre of interest lies at panel pixel `gazePanel`, that
// land on the panel (plus `margin` pixels), each carried into the rendered image (pixels) through
// the lens (green channel). `centre` is the lens centre, normalised.
[[nodiscard]] std::vector<glm::vec2> panelPointsInImage(const foveation::PointSet& set,
                                                        glm::vec2 gazePanel, const LensModel& lens,
                                                        glm::vec2 centre, float margin);

// Both layouts for the eye looking at image pixel `gazeImage`: how many points each samples (the
// rays per frame, at R rays a point), and the points per 1000 image pixels in four rings around
// the lens centre (by normalised radius 0-0.25, 0.25-0.5, 0.5-0.75, 0.75-1).
struct LayoutComparison {
    std::size_t imagePoints = 0, panelPoints = 0;
    std::array<double, 4> imageDensity{}, panelDensity{};
    glm::vec2 gazePanel{};
};
[[nodiscard]] LayoutComparison compareLayouts(const foveation::PointSet& set, glm::vec2 gazeImage,
                                              const LensModel& lens, glm::vec2 centre,
                                              float margin);

} // namespace gt::display
