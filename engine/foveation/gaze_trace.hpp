#pragma once
// Recorded gaze for driving the renderer: CSV with a header line `t_ms,x,y` and one sample per
// line (milliseconds, screen pixels, origin top-left). `gazetrace track --out` writes the same
// format, so recorded gaze replays in the renderer. Times must increase.
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace gt::foveation {

struct GazeTraceSample {
    double tMs = 0.0;
    glm::vec2 position{};
};

class GazeTrace {
public:
    // Throws gt::LoadError naming the file and line for anything malformed.
    [[nodiscard]] static GazeTrace load(const std::filesystem::path& file);
    [[nodiscard]] static GazeTrace fromSamples(std::vector<GazeTraceSample> samples);

    [[nodiscard]] const std::vector<GazeTraceSample>& samples() const noexcept { return mSamples; }
    [[nodiscard]] double startMs() const { return mSamples.front().tMs; }
    [[nodiscard]] double endMs() const { return mSamples.back().tMs; }
    // Linear interpolation, clamped at both ends.
    [[nodiscard]] glm::vec2 at(double tMs) const;

private:
    std::vector<GazeTraceSample> mSamples;
};

} // namespace gt::foveation
