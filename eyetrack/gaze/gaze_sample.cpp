#include "gaze/gaze_sample.hpp"

#include <cmath>

namespace gt::eyetrack {

const char* toString(GazeEvent e) noexcept {
    switch (e) {
    case GazeEvent::Fixation:
        return "fixation";
    case GazeEvent::Saccade:
        return "saccade";
    case GazeEvent::Blink:
        return "blink";
    }
    return "fixation";
}

bool isValid(const GazeSample& s) noexcept {
    return std::isfinite(s.x) && std::isfinite(s.y) && s.confidence > 0.0f;
}

} // namespace gt::eyetrack
