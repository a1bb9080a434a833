#pragma once
// The one value the eye tracker hands to the renderer (docs/ARCHITECTURE.md): a gaze point in
// screen pixels with its time, confidence, what the eye is doing, and whether a saccade started
// (the renderer resets its temporal history on it).
#include <cstdint>

namespace gt::eyetrack {

enum class GazeEvent { Fixation, Saccade, Blink };
[[nodiscard]] const char* toString(GazeEvent e) noexcept;

struct GazeSample {
    double tMs = 0.0;
    float x = 0.0f;
    float y = 0.0f;
    float confidence = 0.0f;
    bool saccade = false; // true on the first sample of a saccade
    GazeEvent event = GazeEvent::Fixation;
};

[[nodiscard]] bool isValid(const GazeSample& s) noexcept;

} // namespace gt::eyetrack
