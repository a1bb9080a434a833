#pragma once
// A point set with a point at every canvas pixel centre (24 x 16 display, 48 x 32 canvas):
// every screen pixel centre is a point, so interpolants must return the samples there.
#include <cstdint>
#include <vector>

#include "foveation/point_set.hpp"

namespace gt::test {

inline foveation::PointSet pixelCentreGrid() {
    foveation::PointSetParams p;
    p.display = {"grid", 24, 16, 1.0};
    std::vector<foveation::Point> pts;
    for (uint32_t y = 0; y < 32; ++y) {
        for (uint32_t x = 0; x < 48; ++x)
            pts.push_back({static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f, 0.6f});
    }
    return foveation::PointSet::fromPoints(p, pts);
}

} // namespace gt::test
