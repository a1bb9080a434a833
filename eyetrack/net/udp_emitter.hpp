#pragma once
// Sends each gaze sample as one JSON datagram to udp://HOST:PORT, for other programs (and
// `gazetrace demo --gaze udp:PORT`):
// {"t_ms":..,"eye":"both|left|right","yaw_deg":..,"pitch_deg":..,"x":..,"y":..,
//  "screen":[W,H],"confidence":..,"event":"fixation|saccade|blink","saccade_onset":..}
// plus, on binocular "both" datagrams, "vergence_deg" and "fixation_cm" when known.
// Angles are degrees from the eye's straight-ahead (yaw right, pitch up); x, y are pixels of
// the calibration's screen, given where one is known.
#include <cstdint>
#include <optional>
#include <string>

#include <netinet/in.h>

#include "gaze/display_geometry.hpp"
#include "gaze/gaze_sample.hpp"

namespace gt::eyetrack {

// Where the datagrams go.
struct UdpEndpoint {
    std::string host;       // an IPv4 address, dotted
    std::uint16_t port = 0; // 1-65535
};

class UdpEmitter {
public:
    // Throws EyetrackError for a host that is not an IPv4 address, port 0, or no socket.
    // `display`: the calibration's screen, for the angles and the screen size in each datagram.
    UdpEmitter(const UdpEndpoint& to, const DisplayGeometry& display);
    ~UdpEmitter();
    UdpEmitter(const UdpEmitter&) = delete;
    UdpEmitter& operator=(const UdpEmitter&) = delete;

    // Best effort, like any UDP stream: returns false if the datagram could not be sent.
    bool send(const GazeSample& s);
    [[nodiscard]] static std::string toJson(const GazeSample& s, const DisplayGeometry& display,
                                            const char* eye = "both");
    // Binocular tracking: each eye's sample ("left" / "right", with that eye's own angles),
    // then the combined one ("both") with the vergence when both eyes fixate.
    bool sendEye(const GazeSample& s, const char* eye, cv::Point2d anglesDeg);
    bool sendCombined(const GazeSample& s, std::optional<double> vergenceDeg,
                      std::optional<double> fixationCm);

private:
    bool sendText(const std::string& text);
    DisplayGeometry mDisplay;
    int mSocket = -1;
    sockaddr_in mTo{};
};

} // namespace gt::eyetrack
