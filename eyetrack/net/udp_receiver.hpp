#pragma once
// The other end of UdpEmitter: listens on a UDP port and hands out the gaze datagrams that pass
// parseGazeDatagram, in the order they arrived. Whatever arrives never stops it: a refused
// datagram is dropped and counted, and the count is reported through a warning callback, with
// the first refusal's reason, at 1, 10, 100, ... drops and once more when the receiver closes.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "net/gaze_datagram.hpp"
#include "net/udp_emitter.hpp"

namespace gt::eyetrack {

// Datagrams read in one call of next() before it returns none, so that a flood cannot hold the
// frame loop that polls it; the rest wait in the socket for the next call.
inline constexpr int kMaxGazeDatagramsPerPoll = 1024;

// Counts refused datagrams and says so without flooding the log: the first refusal with its
// reason, then the count at every power of ten, and the final count at flush().
class DatagramDropLog {
public:
    using Warn = std::function<void(const std::string&)>;
    DatagramDropLog(std::string source, Warn warn);
    void drop(const std::string& reason);
    void flush();                       // the count, when it grew since the last line
    void note(const std::string& what); // any other warning of the same source
    [[nodiscard]] std::uint64_t dropped() const noexcept { return mDropped; }

private:
    void report();
    std::string mSource;
    Warn mWarn;
    std::string mFirst;
    std::uint64_t mDropped = 0, mReported = 0, mNextReport = 1;
};

class UdpGazeReceiver {
public:
    using Warn = DatagramDropLog::Warn;
    // Listens on `at` (an IPv4 address in dotted form; port 0: any free one). `label` starts
    // every warning ("gaze udp:5005"). Binding beyond loopback warns once that anyone on that
    // network can steer the gaze. Throws EyetrackError when it cannot listen there.
    UdpGazeReceiver(const UdpEndpoint& at, std::string label, Warn warn);
    ~UdpGazeReceiver(); // reports the final drop count
    UdpGazeReceiver(const UdpGazeReceiver&) = delete;
    UdpGazeReceiver& operator=(const UdpGazeReceiver&) = delete;

    // The next datagram that arrived and passed, or none when the socket has no more (or this
    // call read kMaxGazeDatagramsPerPoll). A datagram that gives one eye's angles only is
    // refused until one has placed the gaze as a whole (placesGaze): before that there is no
    // gaze to pair it with, and the viewer's gaze cannot be derived from one eye's angles.
    [[nodiscard]] std::optional<GazeDatagram> next();
    [[nodiscard]] std::uint64_t dropped() const noexcept { return mDrops.dropped(); }
    [[nodiscard]] std::uint16_t port() const noexcept { return mPort; }

private:
    int mSocket = -1;
    std::uint16_t mPort = 0;
    DatagramDropLog mDrops;
    bool mPlaced = false;
    int mReadThisPoll = 0;
};

// Whether an IPv4 address in dotted form lies on this machine's loopback (127.0.0.0/8).
[[nodiscard]] bool isLoopbackIpv4(const std::string& ipv4);

} // namespace gt::eyetrack
