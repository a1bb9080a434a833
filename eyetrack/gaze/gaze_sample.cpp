#include "gaze_sample.hpp"

#include <cmath>

namespace gt::eyetrack {

bool isValid(const GazeSample& s) noexcept {
    return std::isfinite(s.x) && std::isfinite(s.y) && s.confidence > 0.0f;
}

} // namespace gt::eyetrack
