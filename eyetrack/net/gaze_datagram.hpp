#pragma once
// One gaze datagram as UdpEmitter writes it (udp_emitter.hpp names the fields), read as typed
// values. The bytes come from anyone who can reach the port, so every field is checked for its
// type and range; a datagram that fails any check is refused as a whole, with one line saying
// which field and why, and the receiver goes on with the next one.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include <opencv2/core/types.hpp>

#include "gaze/gaze_sample.hpp"

namespace gt::eyetrack {

// A datagram of `gazetrace track --emit` is under 400 bytes; a larger one is not ours.
inline constexpr std::size_t kMaxGazeDatagramBytes = 2048;
// Pixels further than this from the screen's corner are no gaze on any screen (and would lose
// their precision as the renderer's floats).
inline constexpr double kMaxGazeScreenPx = 1.0e6;
// The screen a datagram names ("screen": [W, H]): Vulkan's largest image side is far below.
inline constexpr int kMaxGazeScreenSidePx = 65536;
// Gaze angles are measured from straight ahead and lie strictly inside +-90 degrees (the
// display's pixelOfAngles is defined there only).
inline constexpr double kMaxGazeAngleDeg = 90.0;
// Time stamps beyond 2^53 ms no longer count single milliseconds in a double.
inline constexpr double kMaxGazeTimeMs = 9.0e15;

enum class DatagramEye { Both, Left, Right };

struct GazeDatagram {
    double tMs = 0.0; // the sender's clock; 0 when the datagram has none
    DatagramEye eye = DatagramEye::Both;
    std::optional<cv::Point2d> anglesDeg; // yaw_deg (right), pitch_deg (up) of `eye`
    std::optional<cv::Point2d> screenPx;  // x, y on the sender's screen
    std::optional<cv::Size> screen;       // that screen's size in pixels
    double confidence = 1.0;
    std::optional<GazeEvent> event;
    bool saccadeOnset = false;
    std::optional<double> vergenceDeg;
    std::optional<double> fixationCm;

    // Whether the datagram says where the viewer looks as a whole: screen pixels, or the angles
    // of both eyes together. One eye's angles alone say where that eye looks only.
    [[nodiscard]] bool placesGaze() const noexcept {
        return screenPx.has_value() || (anglesDeg.has_value() && eye == DatagramEye::Both);
    }
};

// Either a datagram or why there is none.
struct DatagramReading {
    std::optional<GazeDatagram> datagram;
    std::string refusal; // one line, empty when `datagram` is set; never echoes raw bytes
};

// Reads one datagram. It must be at most kMaxGazeDatagramBytes of UTF-8 holding one JSON object
// with a gaze position: x and y, or yaw_deg and pitch_deg (or both pairs). Every other field is
// optional, but when present has the emitter's type and a sane range; unknown fields are
// ignored (a newer sender may add some). Throws nothing but std::bad_alloc.
[[nodiscard]] DatagramReading parseGazeDatagram(std::string_view bytes);

} // namespace gt::eyetrack
