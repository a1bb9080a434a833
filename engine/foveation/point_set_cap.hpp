#pragma once
// Never more rays than the reference: a view traces the points of its set that land on screen
// or within the sampling margin of thesis section 4.2, for the gaze of the moment. Its rays per
// frame stay within the full-resolution frame's W x H x (rays per point) when no gaze puts more
// than W x H points there. The acuity model of thesis eqs. (1)-(4) gives a spacing of at least
// sqrt(1/pi) px, up to about 1.6 points per pixel; where a display is coarser than the eye
// resolves (320 x 240 at 85 degrees: 0.56 px almost everywhere), the set is thinned by a floor
// under the spacing. Local densities above one point per pixel stay allowed (the thesis's set
// has them at the centre); only the total per gaze is capped.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "foveation/point_set.hpp"
#include "foveation/sample_canvas.hpp"

namespace gt::foveation {

struct TracedPoints {
    std::size_t count = 0; // the most points traced at any gaze
    uint32_t gazeX = 0;    // a whole-pixel gaze that traces that many
    uint32_t gazeY = 0;
};

// The exact maximum of PointSet::countOnScreen(gx, gy, margin) over every whole-pixel gaze
// 0 <= gx <= W, 0 <= gy <= H (the set shifts by whole pixels, sample_canvas.hpp), by sliding
// windows over per-row point counts: O(canvas + points), memory O(points). `margin` is rounded
// to whole pixels.
[[nodiscard]] TracedPoints maxPointsTraced(const PointSet& set, float margin = kSampleMargin);

// Points a view of the set's display may trace at once: one per screen pixel.
[[nodiscard]] std::size_t screenPointCap(const DisplayProfile& display) noexcept;

// Spacing floors to try, smallest first, when `params`' set traces more than the cap: the
// first is the closed-form floor at which the densest possible dart-throwing set, the saturated
// random-sequential-adsorption density 0.547 * 4 / (pi p^2) points per pixel, would trace no
// more than the cap with the gaze at the centre (radially decreasing density: the centre is
// the worst gaze); each next one 3 % larger, all rounded up to 1/1024 px so that a floor, and
// the cache file named after it, are the same on every machine.
[[nodiscard]] std::vector<double> spacingFloors(const PointSetParams& params, std::size_t cap);

} // namespace gt::foveation
