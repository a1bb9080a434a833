#pragma once
// The point-set parameters the cache fuzz target loads with and its seeds are made with: a
// small display, so a seed is a few hundred points and the neighbour index builds in
// microseconds.
#include "foveation/point_set.hpp"

namespace gt::fuzz {

inline foveation::PointSetParams pointSetParams() {
    foveation::PointSetParams p;
    p.display = {"fuzz", 64, 48, 1.0};
    p.scale = 40.0;
    return p;
}

} // namespace gt::fuzz
