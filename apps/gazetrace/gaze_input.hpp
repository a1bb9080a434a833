#pragma once
// Where the viewer looks, from any source, behind one interface: a fixed point, a recorded trace,
// the mouse, the eye tracker (a live or recorded camera through the calibration), or samples sent
// over UDP by `gazetrace track --emit`. The renderer only ever sees the result as a value (a
// view's gaze in pixels), so every source drives every front end, and a trace drives the tests.
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <glm/glm.hpp>

namespace gt::app {

using SteadyClock = std::chrono::steady_clock;

struct GazeReading {
    glm::vec2 screenPx{};     // pixels, origin top-left: the window's, or the screen's (below)
    bool windowPixels = true; // false: screenPx is on the screen (tracker, UDP): subtract the
                              // window's position
    // The gaze as angles (degrees; yaw right, pitch up) where the source knows them (angle
    // traces, the tracker, UDP): both eyes, and each tracked eye. They win over screenPx.
    std::optional<glm::vec2> anglesDeg;
    std::optional<glm::vec2> eyeAnglesDeg[2];
    // When the sample was taken, for gaze-to-photon latency: the camera frame's time for the eye
    // tracker, the poll for the mouse, the read for a trace (which has no clock of its own).
    SteadyClock::time_point sampled{};
    bool saccade = false;    // a saccade began since the last reading: drop temporal history
    float confidence = 1.0f; // the detector's, for the tracker and UDP; 1 for the others
    uint64_t sequence = 0;   // increases with every new sample the source received
    double sourceMs = 0.0;   // the sample's own time stamp (t_ms of a trace or a datagram)
};

class GazeInput {
public:
    virtual ~GazeInput() = default;
    // The newest gaze at `frameMs` (milliseconds since the loop started); empty while there is
    // none yet. Throws gt::Error when the source failed.
    [[nodiscard]] virtual std::optional<GazeReading> read(double frameMs) = 0;
    [[nodiscard]] virtual std::string describe() const = 0;
};

struct GazeInputContext {
    std::string calibration; // for track:
    // The cursor in window pixels (mouse), and the window's position on the screen (screen
    // pixels from the tracker or UDP become window pixels by subtracting it).
    std::function<glm::vec2()> cursor;
    // Screen pixels per window pixel is 1: the demo's window sits on the desktop profile's
    // screen; a tracker calibrated on another screen size is scaled to it.
    glm::uvec2 screenPx{1920, 1080};
};

// fixed:X,Y | mouse | trace:FILE.csv | track:SOURCE | udp:PORT (binds 127.0.0.1) |
// udp:HOST:PORT (a HOST outside 127.0.0.0/8 warns that anyone on the network can steer the
// gaze). Opens the source now, so a bad one fails before any work (one line).
[[nodiscard]] std::unique_ptr<GazeInput> openGazeInput(const std::string& spec,
                                                       const GazeInputContext& context);

} // namespace gt::app
