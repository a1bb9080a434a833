#pragma once
// The one value the eye tracker hands to the renderer (docs/ARCHITECTURE.md): a gaze point in
// screen pixels with its time, confidence and whether a saccade started.
#include <cstdint>

namespace gt::eyetrack {

struct GazeSample {
    double tMs = 0.0;
    float x = 0.0f;
    float y = 0.0f;
    float confidence = 0.0f;
    bool saccade = false;
};

[[nodiscard]] bool isValid(const GazeSample& s) noexcept;

} // namespace gt::eyetrack
