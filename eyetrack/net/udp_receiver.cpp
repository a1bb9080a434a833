#include "net/udp_receiver.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include "error.hpp"

namespace gt::eyetrack {

DatagramDropLog::DatagramDropLog(std::string source, Warn warn)
    : mSource(std::move(source)), mWarn(std::move(warn)) {
    if (!mWarn) {
        mWarn = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
    }
}

void DatagramDropLog::drop(const std::string& reason) {
    if (mDropped == 0) {
        mFirst = reason;
    }
    ++mDropped;
    if (mDropped == mNextReport) {
        report();
        mNextReport = mNextReport > UINT64_MAX / 10 ? UINT64_MAX : mNextReport * 10;
    }
}

void DatagramDropLog::note(const std::string& what) {
    mWarn(mSource + ": " + what);
}

void DatagramDropLog::flush() {
    if (mDropped != mReported) {
        report();
    }
}

void DatagramDropLog::report() {
    mReported = mDropped;
    if (mDropped == 1) {
        mWarn(mSource + ": dropped a datagram: " + mFirst + " (the session goes on)");
    } else {
        mWarn(mSource + ": dropped " + std::to_string(mDropped) + " datagrams (first: " + mFirst +
              ")");
    }
}

bool isLoopbackIpv4(const std::string& ipv4) {
    in_addr a{};
    return ::inet_pton(AF_INET, ipv4.c_str(), &a) == 1 && (ntohl(a.s_addr) >> 24) == 127;
}

UdpGazeReceiver::UdpGazeReceiver(const UdpEndpoint& at, std::string label, Warn warn)
    : mDrops(label, std::move(warn)) {
    auto bad = [&](const std::string& why) { return EyetrackError(label + ": " + why); };
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(at.port);
    if (::inet_pton(AF_INET, at.ipv4.c_str(), &addr.sin_addr) != 1) {
        throw bad("host must be an IPv4 address or localhost");
    }
    mSocket = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (mSocket < 0) {
        throw bad(std::strerror(errno));
    }
    socklen_t length = sizeof(addr);
    if (::bind(mSocket, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) != 0 ||
        ::getsockname(mSocket, reinterpret_cast<sockaddr*>(&addr), &length) != 0) {
        const std::string why = std::strerror(errno);
        ::close(mSocket);
        throw bad("cannot listen: " + why);
    }
    mPort = ntohs(addr.sin_port);
    if (!isLoopbackIpv4(at.ipv4)) {
        const std::string where = addr.sin_addr.s_addr == htonl(INADDR_ANY)
                                      ? "every network interface"
                                      : at.ipv4 + ", beyond this machine";
        mDrops.note("listening on " + where +
                    ": anyone on the network can steer the gaze (udp:PORT listens on this "
                    "machine only)");
    }
}

UdpGazeReceiver::~UdpGazeReceiver() {
    try {
        mDrops.flush();
    } catch (...) { // a warning that cannot be built (out of memory) is not worth a terminate
    }
    ::close(mSocket);
}

std::optional<GazeDatagram> UdpGazeReceiver::next() {
    char buffer[kMaxGazeDatagramBytes];
    while (mReadThisPoll < kMaxGazeDatagramsPerPoll) {
        // MSG_TRUNC: the datagram's own length, though only the buffer's worth is copied.
        const ssize_t n = ::recv(mSocket, buffer, sizeof(buffer), MSG_TRUNC);
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            break; // EAGAIN: drained (or an error the next poll meets again)
        }
        ++mReadThisPoll;
        if (static_cast<std::size_t>(n) > sizeof(buffer)) {
            mDrops.drop("the datagram has " + std::to_string(n) + " bytes, over the limit of " +
                        std::to_string(kMaxGazeDatagramBytes));
            continue;
        }
        DatagramReading r = parseGazeDatagram({buffer, static_cast<std::size_t>(n)});
        if (!r.datagram) {
            mDrops.drop(r.refusal);
            continue;
        }
        if (!r.datagram->placesGaze() && !mPlaced) {
            mDrops.drop(std::string("a datagram gives only the ") +
                        (r.datagram->eye == DatagramEye::Left ? "left" : "right") +
                        " eye's angles and no gaze has arrived to pair them with (it needs x and "
                        "y, or eye \"both\")");
            continue;
        }
        mPlaced = true;
        return r.datagram;
    }
    mReadThisPoll = 0;
    return std::nullopt;
}

} // namespace gt::eyetrack
