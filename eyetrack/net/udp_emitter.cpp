#include "net/udp_emitter.hpp"

#include <cmath>

#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "error.hpp"

namespace gt::eyetrack {

UdpEmitter::UdpEmitter(const UdpEndpoint& to, const DisplayGeometry& display) : mDisplay(display) {
    auto bad = [&](const std::string& why) {
        return EyetrackError("gaze receiver " + to.ipv4 + ":" + std::to_string(to.port) + ": " +
                             why);
    };
    if (to.port == 0) throw bad("port 0 is outside 1..65535");
    mTo.sin_family = AF_INET;
    mTo.sin_port = htons(to.port);
    if (inet_pton(AF_INET, to.ipv4.c_str(), &mTo.sin_addr) != 1)
        throw bad("the host is not an IPv4 address");
    mSocket = ::socket(AF_INET, SOCK_DGRAM, 0);
    if (mSocket < 0) throw bad("cannot create a UDP socket");
}

UdpEmitter::~UdpEmitter() {
    if (mSocket >= 0) ::close(mSocket);
}

namespace {

nlohmann::json datagram(const GazeSample& s, const DisplayGeometry& d, const char* eye) {
    const cv::Point2d a = d.anglesDeg({s.x, s.y});
    return {{"t_ms", s.tMs},
            {"eye", eye},
            {"yaw_deg", a.x},
            {"pitch_deg", a.y},
            {"x", s.x},
            {"y", s.y},
            {"screen", {d.widthPx, d.heightPx}},
            {"confidence", s.confidence},
            {"event", toString(s.event)},
            {"saccade_onset", s.saccade}};
}

} // namespace

std::string UdpEmitter::toJson(const GazeSample& s, const DisplayGeometry& d, const char* eye) {
    return datagram(s, d, eye).dump();
}

bool UdpEmitter::sendText(const std::string& text) {
    return ::sendto(mSocket, text.data(), text.size(), 0, reinterpret_cast<const sockaddr*>(&mTo),
                    sizeof(mTo)) == static_cast<ssize_t>(text.size());
}

bool UdpEmitter::send(const GazeSample& s) {
    return sendText(toJson(s, mDisplay));
}

bool UdpEmitter::sendEye(const GazeSample& s, const char* eye, cv::Point2d anglesDeg) {
    nlohmann::json j = datagram(s, mDisplay, eye);
    j["yaw_deg"] = anglesDeg.x;
    j["pitch_deg"] = anglesDeg.y;
    return sendText(j.dump());
}

bool UdpEmitter::sendCombined(const GazeSample& s, std::optional<double> vergenceDeg,
                              std::optional<double> fixationCm) {
    nlohmann::json j = datagram(s, mDisplay, "both");
    if (vergenceDeg) j["vergence_deg"] = *vergenceDeg;
    if (fixationCm && std::isfinite(*fixationCm)) j["fixation_cm"] = *fixationCm;
    return sendText(j.dump());
}

} // namespace gt::eyetrack
