#pragma once
// Sends each gaze sample as one JSON datagram to udp://HOST:PORT, for other programs:
// {"t_ms":..,"x":..,"y":..,"confidence":..,"event":"fixation|saccade|blink","saccade_onset":..}
#include <string>

#include <netinet/in.h>

#include "gaze/gaze_sample.hpp"

namespace gt::eyetrack {

class UdpEmitter {
public:
    // url: udp://IPV4:PORT or udp://localhost:PORT. Throws EyetrackError for a bad URL.
    explicit UdpEmitter(const std::string& url);
    ~UdpEmitter();
    UdpEmitter(const UdpEmitter&) = delete;
    UdpEmitter& operator=(const UdpEmitter&) = delete;

    // Best effort, like any UDP stream: returns false if the datagram could not be sent.
    bool send(const GazeSample& s);
    [[nodiscard]] static std::string toJson(const GazeSample& s);

private:
    int mSocket = -1;
    sockaddr_in mTo{};
};

} // namespace gt::eyetrack
