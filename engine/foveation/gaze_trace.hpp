#pragma once
// Recorded gaze for driving the renderer: CSV with a header line and one sample per line.
//  - `t_ms,x,y`: milliseconds and screen pixels, origin top-left (`gazetrace track --out` writes
//    this, so recorded gaze replays in the renderer);
//  - `t_ms,yaw_deg,pitch_deg[,eye]`: gaze angles in degrees from the eye's straight-ahead (yaw
//    right, pitch up, as the tracker's calibration fits them), optionally per eye (`left`,
//    `right` or `both`); they land on a desktop screen through its physical geometry and in an
//    HMD through each eye's own projection.
// Times must increase (per eye).
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace gt::foveation {

enum class GazeUnits { Pixels, AnglesDeg };
enum class GazeEye { Both, Left, Right };

struct GazeTraceSample {
    double tMs = 0.0;
    glm::vec2 position{}; // pixels (x, y) or angles (yaw, pitch), see GazeTrace::units()
    GazeEye eye = GazeEye::Both;
};

class GazeTrace {
public:
    // Throws gt::LoadError naming the file and line for anything malformed.
    [[nodiscard]] static GazeTrace load(const std::filesystem::path& file);
    [[nodiscard]] static GazeTrace fromSamples(std::vector<GazeTraceSample> samples);

    [[nodiscard]] static GazeTrace fromSamples(std::vector<GazeTraceSample> samples,
                                               GazeUnits units);

    [[nodiscard]] const std::vector<GazeTraceSample>& samples() const noexcept { return mSamples; }
    [[nodiscard]] GazeUnits units() const noexcept { return mUnits; }
    // The first and the last sample's time over every eye (per-eye rows may interleave: the
    // file's last row is not always the latest; found by fuzzing).
    [[nodiscard]] double startMs() const noexcept { return mStartMs; }
    [[nodiscard]] double endMs() const noexcept { return mEndMs; }
    // Linear interpolation, clamped at both ends: the samples for both eyes (or, when the trace
    // has only per-eye samples, the left eye's).
    [[nodiscard]] glm::vec2 at(double tMs) const;
    // One eye: its own samples, else those for both eyes.
    [[nodiscard]] glm::vec2 at(double tMs, GazeEye eye) const;
    [[nodiscard]] bool hasEye(GazeEye eye) const noexcept;

private:
    std::vector<GazeTraceSample> mSamples;
    std::vector<GazeTraceSample> mPerEye[3]; // indexed by GazeEye
    GazeUnits mUnits = GazeUnits::Pixels;
    double mStartMs = 0.0, mEndMs = 0.0;
};

} // namespace gt::foveation
