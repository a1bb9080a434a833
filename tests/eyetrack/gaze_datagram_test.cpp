// Gaze datagrams from anyone who can reach the port: the typed reader refuses every malformed
// one with a reason (no exception escapes), the receiver drops and counts it and delivers the
// next good one, warns when it listens beyond loopback, and never takes one eye's angles for
// the viewer's gaze.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include "error.hpp"
#include "net/gaze_datagram.hpp"
#include "net/udp_emitter.hpp"
#include "net/udp_receiver.hpp"

using namespace gt::eyetrack;

namespace {

std::string refusalOf(std::string_view bytes) {
    const DatagramReading r = parseGazeDatagram(bytes);
    EXPECT_FALSE(r.datagram.has_value()) << bytes;
    EXPECT_FALSE(r.refusal.empty()) << bytes;
    return r.refusal;
}

// Found by a hostile-input run: a saccade_onset of the wrong type escaped the reader as
// nlohmann's type_error and ended the demo and xr sessions.
TEST(GazeDatagram, RefusesASaccadeOnsetThatIsNoBoolean) {
    EXPECT_EQ(refusalOf(R"({"x":100,"y":100,"saccade_onset":1})"),
              "field saccade_onset is a number, must be a boolean");
    EXPECT_EQ(refusalOf(R"({"x":100,"y":100,"saccade_onset":"yes"})"),
              "field saccade_onset is a string, must be a boolean");
    EXPECT_EQ(refusalOf(R"({"x":100,"y":100,"saccade_onset":null})"),
              "field saccade_onset is null, must be a boolean");
}

TEST(GazeDatagram, RefusesWrongTypesAndRangesNamingTheField) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"({"x":"100","y":100})", "field x is a string, must be a number"},
        {R"({"x":100,"y":[1]})", "field y is an array, must be a number"},
        {R"({"x":1e300,"y":100})", "field x is 1e+300, must lie within [-1e+06, 1e+06]"},
        {R"({"yaw_deg":90,"pitch_deg":0})", "field yaw_deg is 90, must lie within (-90, 90)"},
        {R"({"yaw_deg":1,"pitch_deg":-1e9})",
         "field pitch_deg is -1e+09, must lie within (-90, 90)"},
        {R"({"x":100,"y":100,"confidence":2})", "field confidence is 2, must lie within [0, 1]"},
        {R"({"x":100,"y":100,"t_ms":true})", "field t_ms is a boolean, must be a number"},
        {R"({"x":100,"y":100,"eye":"middle"})",
         R"(field eye is "middle", must be "both", "left" or "right")"},
        {R"({"x":100,"y":100,"eye":3})", "field eye is a number, must be a string"},
        {R"({"x":100,"y":100,"event":{}})", "field event is an object, must be a string"},
        {R"({"x":100,"y":100,"screen":[1920]})",
         "field screen has 1 entries, must be [width, height]"},
        {R"({"x":100,"y":100,"screen":[1920,-1]})",
         "field screen is outside 1..65536 pixels a side"},
        {R"({"x":100,"y":100,"screen":[1920.5,1080]})",
         "field screen is a number, must be [width, height] in whole pixels"},
        {R"({"x":100,"y":100,"vergence_deg":-3})",
         "field vergence_deg is -3, must lie within [0, 180]"},
        {R"({"x":100,"y":100,"fixation_cm":0})",
         "field fixation_cm is 0, must lie within (0, 1.79769e+308)"},
        {R"({"x":100})", "field y is missing (x and y come together)"},
        {R"({"pitch_deg":3})", "field yaw_deg is missing (yaw_deg and pitch_deg come together)"},
        {R"({"t_ms":5,"confidence":1})",
         "the datagram has no gaze: it needs x and y, or yaw_deg and pitch_deg"},
        {R"([1,2])", "the datagram is an array, must be a JSON object"},
        {R"("x")", "the datagram is a string, must be a JSON object"},
    };
    for (const auto& [bytes, why] : cases) {
        EXPECT_EQ(refusalOf(bytes), why) << bytes;
    }
}

// JSON has no NaN or infinity, but a number past a double's range reaches one, and some senders
// write NaN anyway.
TEST(GazeDatagram, RefusesNumbersBeyondADoubleAndNonJson) {
    EXPECT_EQ(refusalOf(R"({"x":1e400,"y":100})"),
              "the datagram holds a number beyond a double's range");
    EXPECT_EQ(refusalOf(R"({"x":-1e400,"y":100})"),
              "the datagram holds a number beyond a double's range");
    EXPECT_EQ(refusalOf(R"({"x":NaN,"y":100})"), "the datagram is not JSON (at byte offset 5)");
    EXPECT_EQ(refusalOf(""), "the datagram is not JSON (at byte offset 0)");
    EXPECT_EQ(refusalOf(R"({"x":1,"y":2} {})"), "the datagram is not JSON (at byte offset 14)");
}

TEST(GazeDatagram, RefusesNonUtf8AndOversizedDatagrams) {
    EXPECT_EQ(refusalOf("{\"x\":1,\"y\":2,\"eye\":\"\xff\"}"),
              "the datagram is not UTF-8 (at byte offset 20)");
    EXPECT_EQ(refusalOf("{\"x\":1,\"y\":2,\"eye\":\"\xc0\xaf\"}"), // overlong '/'
              "the datagram is not UTF-8 (at byte offset 20)");
    EXPECT_EQ(refusalOf("{\"x\":1,\"y\":2,\"eye\":\"\xed\xa0\x80\"}"), // a surrogate
              "the datagram is not UTF-8 (at byte offset 20)");
    EXPECT_EQ(refusalOf("{\"x\":1,\"y\":2,\"eye\":\"\xe2\x82\"}"), // cut short
              "the datagram is not UTF-8 (at byte offset 20)");
    std::string big = R"({"x":1,"y":2,"pad":")" + std::string(kMaxGazeDatagramBytes, 'a') + "\"}";
    EXPECT_EQ(refusalOf(big),
              "the datagram has " + std::to_string(big.size()) + " bytes, over the limit of 2048");
    // Valid UTF-8 beyond ASCII is fine in a string; a long value is shown cut short.
    EXPECT_TRUE(parseGazeDatagram("{\"x\":1,\"y\":2,\"note\":\"gr\xc3\xbc\xc3\x9f\"}").datagram);
    const std::string shown = refusalOf(R"({"x":1,"y":2,"eye":")" + std::string(500, 'q') + "\"}");
    EXPECT_LT(shown.size(), 100u) << shown;
}

// What UdpEmitter writes is what the reader reads, field for field.
TEST(GazeDatagram, ReadsWhatTheEmitterWrites) {
    const DisplayGeometry display;
    GazeSample s;
    s.tMs = 12.5;
    s.x = 100.0f;
    s.y = 200.0f;
    s.confidence = 0.75f;
    s.saccade = true;
    s.event = GazeEvent::Saccade;
    const DatagramReading r = parseGazeDatagram(UdpEmitter::toJson(s, display, "right"));
    ASSERT_TRUE(r.datagram) << r.refusal;
    const GazeDatagram& d = *r.datagram;
    EXPECT_DOUBLE_EQ(d.tMs, 12.5);
    EXPECT_EQ(d.eye, DatagramEye::Right);
    ASSERT_TRUE(d.screenPx && d.anglesDeg && d.screen && d.event);
    EXPECT_DOUBLE_EQ(d.screenPx->x, 100.0);
    EXPECT_DOUBLE_EQ(d.screenPx->y, 200.0);
    const cv::Point2d a = display.anglesDeg({100.0, 200.0});
    EXPECT_DOUBLE_EQ(d.anglesDeg->x, a.x);
    EXPECT_DOUBLE_EQ(d.anglesDeg->y, a.y);
    EXPECT_EQ(*d.screen, cv::Size(display.widthPx, display.heightPx));
    EXPECT_DOUBLE_EQ(d.confidence, 0.75);
    EXPECT_EQ(*d.event, GazeEvent::Saccade);
    EXPECT_TRUE(d.saccadeOnset);
    EXPECT_TRUE(d.placesGaze()); // it has x, y
    // Two eyes' lines of sight nearly parallel: the emitter sends a far fixation, read as sent.
    const DatagramReading far =
        parseGazeDatagram(R"({"x":1,"y":2,"vergence_deg":1e-7,"fixation_cm":3e11})");
    ASSERT_TRUE(far.datagram) << far.refusal;
    EXPECT_DOUBLE_EQ(*far.datagram->fixationCm, 3e11);
    // A third party's minimal datagram: angles of both eyes only.
    const DatagramReading minimal = parseGazeDatagram(R"({"yaw_deg":-20,"pitch_deg":12.5})");
    ASSERT_TRUE(minimal.datagram) << minimal.refusal;
    EXPECT_TRUE(minimal.datagram->placesGaze());
    EXPECT_FALSE(minimal.datagram->screenPx);
    EXPECT_DOUBLE_EQ(minimal.datagram->confidence, 1.0);
    const DatagramReading oneEye =
        parseGazeDatagram(R"({"eye":"left","yaw_deg":-20,"pitch_deg":12.5})");
    ASSERT_TRUE(oneEye.datagram) << oneEye.refusal;
    EXPECT_FALSE(oneEye.datagram->placesGaze());
}

TEST(DatagramDropLog, SaysTheFirstReasonThenCountsAtPowersOfTenAndAtTheEnd) {
    std::vector<std::string> lines;
    {
        DatagramDropLog log("gaze udp:5005", [&](const std::string& l) { lines.push_back(l); });
        for (int i = 0; i < 17; ++i) {
            log.drop(i == 0 ? "field saccade_onset is a string, must be a boolean" : "other");
        }
        EXPECT_EQ(log.dropped(), 17u);
        log.flush();
        log.flush(); // nothing new: no line
    }
    ASSERT_EQ(lines.size(), 3u);
    EXPECT_EQ(lines[0], "gaze udp:5005: dropped a datagram: field saccade_onset is a string, must "
                        "be a boolean (the session goes on)");
    EXPECT_EQ(lines[1], "gaze udp:5005: dropped 10 datagrams (first: field saccade_onset is a "
                        "string, must be a boolean)");
    EXPECT_EQ(lines[2], "gaze udp:5005: dropped 17 datagrams (first: field saccade_onset is a "
                        "string, must be a boolean)");
}

// A sender on loopback for the receiver's port.
class Sender {
public:
    explicit Sender(std::uint16_t port) : mSocket(::socket(AF_INET, SOCK_DGRAM, 0)) {
        mTo.sin_family = AF_INET;
        mTo.sin_port = htons(port);
        mTo.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    }
    ~Sender() { ::close(mSocket); }
    Sender(const Sender&) = delete;
    Sender& operator=(const Sender&) = delete;
    void send(const std::string& bytes) {
        ASSERT_EQ(::sendto(mSocket, bytes.data(), bytes.size(), 0,
                           reinterpret_cast<const sockaddr*>(&mTo), sizeof(mTo)),
                  static_cast<ssize_t>(bytes.size()));
    }

private:
    int mSocket;
    sockaddr_in mTo{};
};

// Loopback delivers at once, but give the kernel a moment before polling.
std::vector<GazeDatagram> drain(UdpGazeReceiver& rx, std::size_t expected) {
    std::vector<GazeDatagram> got;
    for (int tries = 0; tries < 200 && got.size() < expected; ++tries) {
        while (auto d = rx.next())
            got.push_back(*d);
        if (got.size() < expected) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return got;
}

TEST(UdpGazeReceiver, DropsAHostileDatagramAndDeliversTheNextGoodOne) {
    std::vector<std::string> warnings;
    UdpGazeReceiver rx(UdpEndpoint{"127.0.0.1", 0}, "gaze udp:test",
                       [&](const std::string& l) { warnings.push_back(l); });
    EXPECT_TRUE(warnings.empty()); // loopback: no warning
    Sender tx(rx.port());
    tx.send(R"({"x":100,"y":100,"saccade_onset":1})");
    tx.send(R"({"x":100,"y":100,"saccade_onset":"yes"})");
    tx.send(std::string(3000, '{')); // over the limit, though the socket holds it
    tx.send(R"({"x":640,"y":360,"saccade_onset":true})");
    const auto got = drain(rx, 1);
    ASSERT_EQ(got.size(), 1u);
    ASSERT_TRUE(got[0].screenPx);
    EXPECT_DOUBLE_EQ(got[0].screenPx->x, 640.0);
    EXPECT_TRUE(got[0].saccadeOnset);
    EXPECT_EQ(rx.dropped(), 3u);
    ASSERT_EQ(warnings.size(), 1u); // the first drop only, until the count reaches 10
    EXPECT_EQ(warnings[0], "gaze udp:test: dropped a datagram: field saccade_onset is a number, "
                           "must be a boolean (the session goes on)");
}

TEST(UdpGazeReceiver, SaysTheSizeOfAnOversizedDatagram) {
    std::vector<std::string> warnings;
    {
        UdpGazeReceiver rx(UdpEndpoint{"127.0.0.1", 0}, "gaze udp:test",
                           [&](const std::string& l) { warnings.push_back(l); });
        Sender tx(rx.port());
        tx.send(std::string(3000, ' '));
        tx.send(R"({"x":1,"y":2})");
        EXPECT_EQ(drain(rx, 1).size(), 1u);
    }
    ASSERT_FALSE(warnings.empty());
    EXPECT_NE(warnings[0].find("has 3000 bytes, over the limit of 2048"), std::string::npos)
        << warnings[0];
}

// One eye's angles say nothing of the viewer's gaze as a whole: until a datagram has placed it
// (x, y or both eyes' angles) such a datagram is dropped, not read as the pixel (0, 0).
TEST(UdpGazeReceiver, RefusesOneEyesAnglesUntilTheGazeIsPlaced) {
    std::vector<std::string> warnings;
    UdpGazeReceiver rx(UdpEndpoint{"127.0.0.1", 0}, "gaze udp:test",
                       [&](const std::string& l) { warnings.push_back(l); });
    Sender tx(rx.port());
    tx.send(R"({"eye":"left","yaw_deg":-5,"pitch_deg":2})");
    tx.send(R"({"eye":"both","yaw_deg":-4,"pitch_deg":1})");
    tx.send(R"({"eye":"right","yaw_deg":-3,"pitch_deg":1})");
    const auto got = drain(rx, 2);
    ASSERT_EQ(got.size(), 2u);
    EXPECT_EQ(got[0].eye, DatagramEye::Both);
    EXPECT_EQ(got[1].eye, DatagramEye::Right); // after the gaze is placed, an eye's own angles
    EXPECT_EQ(rx.dropped(), 1u);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("only the left eye's angles"), std::string::npos) << warnings[0];
}

TEST(UdpGazeReceiver, WarnsWhenItListensBeyondLoopback) {
    std::vector<std::string> warnings;
    {
        UdpGazeReceiver rx(UdpEndpoint{"0.0.0.0", 0}, "gaze udp:0.0.0.0:0",
                           [&](const std::string& l) { warnings.push_back(l); });
    }
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0], "gaze udp:0.0.0.0:0: listening on every network interface: anyone on "
                           "the network can steer the gaze (udp:PORT listens on this machine "
                           "only)");
    warnings.clear();
    {
        UdpGazeReceiver rx(UdpEndpoint{"127.0.0.2", 0}, "l",
                           [&](const std::string& l) { warnings.push_back(l); });
    }
    EXPECT_TRUE(warnings.empty());
    EXPECT_TRUE(isLoopbackIpv4("127.255.0.1"));
    EXPECT_FALSE(isLoopbackIpv4("128.0.0.1"));
    EXPECT_FALSE(isLoopbackIpv4("10.0.0.1"));
    EXPECT_THROW(UdpGazeReceiver(UdpEndpoint{"example.com", 0}, "x", nullptr), EyetrackError);
}

} // namespace
