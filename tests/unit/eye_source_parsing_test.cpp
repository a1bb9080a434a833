// The eye tracker's command-line values: frame source specs, gaze models and pupil detectors
// parsed into eyetrack's typed values, and every bad value named in a one-line error.
#include <gtest/gtest.h>

#include <string>
#include <variant>

#include "core/error.hpp"
#include "eye_source_parsing.hpp"
#include "option_parsing.hpp"

using namespace gt::app;
namespace et = gt::eyetrack;

namespace {

// The message of the ArgumentError that parsing `spec` throws; empty when it parses.
std::string errorOf(const std::string& spec) {
    try {
        (void)frameSourceConfig(spec);
    } catch (const gt::ArgumentError& e) {
        return e.what();
    }
    return {};
}

} // namespace

TEST(EyeSourceParsing, V4l2OptionsBecomeTheConfig) {
    const auto config =
        frameSourceConfig("v4l2:/dev/video2?width=640&height=480&fps=90&format=grey");
    const auto* c = std::get_if<et::V4l2Config>(&config);
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->device, "/dev/video2");
    EXPECT_EQ(c->width, 640);
    EXPECT_EQ(c->height, 480);
    EXPECT_DOUBLE_EQ(c->fps, 90.0);
    EXPECT_EQ(c->format, et::V4l2PixelFormat::Grey);
    const auto plain = frameSourceConfig("v4l2:/dev/video0");
    EXPECT_EQ(std::get<et::V4l2Config>(plain).format, et::V4l2PixelFormat::FirstOffered);
    EXPECT_EQ(errorOf("v4l2:/dev/video2?fps=fast"),
              "v4l2:/dev/video2: option fps=fast is not a number in 1..10000");
    EXPECT_EQ(errorOf("v4l2:/dev/video2?format=rgb"),
              "v4l2: unknown format 'rgb' (grey | yuyv | mjpeg)");
    EXPECT_EQ(errorOf("v4l2:/dev/video2?gain=3"),
              "v4l2:/dev/video2: unknown option 'gain' (width, height, fps, format)");
}

TEST(EyeSourceParsing, SyntheticOptionsBecomeTheSimulatorsConfig) {
    const auto config = frameSourceConfig("synthetic:7?preset=hard&frames=12&size=96x72&fps=60");
    const auto* c = std::get_if<et::EyeSimConfig>(&config);
    ASSERT_NE(c, nullptr);
    et::EyeSimConfig hard;
    et::applyPreset(hard, et::EyeSimPreset::Hard);
    EXPECT_EQ(c->seed, 7u);
    EXPECT_EQ(c->frames, 12);
    EXPECT_DOUBLE_EQ(c->fps, 60.0);
    EXPECT_EQ(c->size, cv::Size(96, 72));
    EXPECT_EQ(c->glints, hard.glints);
    EXPECT_DOUBLE_EQ(c->noiseSigma, hard.noiseSigma);
    EXPECT_EQ(errorOf("synthetic:abc"),
              "synthetic:abc: the seed must be a whole number, 0 or more");
    EXPECT_EQ(errorOf("synthetic:1?frames=0"),
              "synthetic:1: option frames=0 is not a whole number in 1..1000000");
    EXPECT_EQ(errorOf("synthetic:1?size=20x10"),
              "synthetic:1: option size width=20 is not a whole number in 32..4096");
    EXPECT_EQ(errorOf("synthetic:1?speed=2"),
              "synthetic:1: unknown option 'speed' (preset, frames, fps, size)");
    EXPECT_EQ(errorOf("synthetic:1?preset=soft"),
              "unknown eyesim preset 'soft' (clean | hard | wild)");
}

TEST(EyeSourceParsing, RecordingsKeepTheirWholePath) {
    const auto video = frameSourceConfig("video:clips/a?b.mkv");
    EXPECT_EQ(std::get<et::VideoFileConfig>(video).path, "clips/a?b.mkv");
    const auto images = frameSourceConfig("images:frames");
    EXPECT_EQ(std::get<et::ImageFolderConfig>(images).folder, "frames");
    EXPECT_DOUBLE_EQ(std::get<et::ImageFolderConfig>(images).fps, 30.0);
}

TEST(EyeSourceParsing, MalformedSpecsAreNamed) {
    EXPECT_EQ(errorOf("camera0"), "frame source 'camera0': expected v4l2:DEVICE, video:FILE, "
                                  "images:DIR or synthetic:SEED");
    EXPECT_EQ(errorOf("ftp:x"),
              "frame source 'ftp:x': unknown kind 'ftp' (v4l2, video, images, synthetic)");
    EXPECT_EQ(errorOf("video:"), "frame source 'video:': nothing after 'video:'");
    EXPECT_EQ(errorOf("synthetic:1?frames"),
              "frame source 'synthetic:1?frames': option 'frames' is not key=value");
}

TEST(EyeSourceParsing, ModelsAndDetectorsByName) {
    EXPECT_EQ(gazeModel("2d"), et::GazeModel::TwoD);
    EXPECT_EQ(gazeModel("3d"), et::GazeModel::ThreeD);
    EXPECT_EQ(pupilDetectorKind("starburst"), et::PupilDetectorKind::Starburst);
    EXPECT_EQ(pupilDetectorKind("blob"), et::PupilDetectorKind::Blob);
    EXPECT_EQ(eyeSimPreset("clean"), et::EyeSimPreset::Clean);
    EXPECT_EQ(eyeSimPreset("hard"), et::EyeSimPreset::Hard);
    EXPECT_EQ(eyeSimPreset("wild"), et::EyeSimPreset::Wild);
    try {
        (void)gazeModel("4d");
        ADD_FAILURE() << "4d accepted";
    } catch (const gt::ArgumentError& e) {
        EXPECT_STREQ(e.what(), "unknown gaze model '4d' (2d | 3d)");
    }
    try {
        (void)pupilDetectorKind("hough");
        ADD_FAILURE() << "hough accepted";
    } catch (const gt::ArgumentError& e) {
        EXPECT_STREQ(e.what(), "unknown pupil detector 'hough' (starburst | blob)");
    }
    EXPECT_EQ(et::makePupilDetector(et::PupilDetectorKind::Blob)->name(), "blob");
    EXPECT_EQ(et::makePupilDetector(et::PupilDetectorKind::Starburst)->name(), "starburst");
}

// fps=1e-300 made a synthetic clip's schedule span 1e303 ms (3.2 GB before it ran); a huge
// width reached the driver, and a negative seed wrapped to 2^64 - 1. Each is refused, naming
// the source and the option.
TEST(EyeSourceParsing, NumericOptionsAreBounded) {
    for (const char* bad :
         {"synthetic:1?fps=1e-300", "synthetic:1?fps=0.5", "synthetic:1?fps=1e9",
          "synthetic:1?fps=nan", "synthetic:1?frames=2000000", "synthetic:1?frames=2.5",
          "synthetic:1?size=99999x240", "synthetic:1?size=320x99999999999", "synthetic:1?size=320",
          "synthetic:-1", "synthetic: 1", "v4l2:/dev/video0?width=1e300",
          "v4l2:/dev/video0?height=9000", "v4l2:/dev/video0?fps=1e-300",
          "v4l2:/dev/video0?fps=inf"}) {
        const std::string message = errorOf(bad);
        EXPECT_FALSE(message.empty()) << bad;
        const std::string source = std::string(bad).substr(0, std::string(bad).find('?'));
        EXPECT_EQ(message.rfind(source, 0), 0u) << message;
    }
    const auto c = std::get<et::EyeSimConfig>(
        frameSourceConfig("synthetic:7?fps=2000&frames=1000000&size=4096x4096"));
    EXPECT_EQ(c.seed, 7u);
    EXPECT_EQ(c.frames, 1000000);
    EXPECT_EQ(c.size, cv::Size(4096, 4096));
    EXPECT_DOUBLE_EQ(c.fps, 2000.0);
}

TEST(EyeSourceParsing, EyeRegionsAreTwoRectangles) {
    const auto [left, right] = parseEyeRegions("0,0,160,120;160,0,160,120");
    EXPECT_EQ(left, cv::Rect(0, 0, 160, 120));
    EXPECT_EQ(right, cv::Rect(160, 0, 160, 120));
    EXPECT_THROW((void)parseEyeRegions("0,0,10"), gt::ArgumentError);
    EXPECT_THROW((void)parseEyeRegions("0,0,160,120;160,0,16,12"), gt::ArgumentError);
    EXPECT_THROW((void)parseEyeRegions("0,0,160,120;160,0,160,120x"), gt::ArgumentError);
}

TEST(EyeSourceParsing, EmitUrlsBecomeEndpoints) {
    const auto to = parseUdpEndpoint("udp://localhost:9000");
    EXPECT_EQ(to.ipv4, "127.0.0.1");
    EXPECT_EQ(to.port, 9000);
    EXPECT_EQ(parseUdpEndpoint("udp://10.0.0.2:65535").ipv4, "10.0.0.2");
    for (const char* bad : {"tcp://1.2.3.4:5", "udp://example.com:5", "udp://127.0.0.1:99999",
                            "udp://127.0.0.1:0", "udp://127.0.0.1"}) {
        EXPECT_THROW((void)parseUdpEndpoint(bad), gt::ArgumentError) << bad;
    }
    try {
        (void)parseUdpEndpoint("udp://127.0.0.1:99999");
    } catch (const gt::ArgumentError& e) {
        EXPECT_STREQ(e.what(), "--emit udp://127.0.0.1:99999: port must be 1-65535");
    }
}
