// The command line's option values become the renderer's typed settings (apps/gazetrace/
// option_parsing): each known name its value, and an unknown one an error naming the option.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "option_parsing.hpp"
#include "support/bad_files.hpp"
#include "vulkan_failure.hpp"

namespace gt::app {
namespace {

TEST(OptionParsing, ParsesSlopes) {
    EXPECT_DOUBLE_EQ(parseSlope("A"), foveation::kSlopeA);
    EXPECT_DOUBLE_EQ(parseSlope("B"), foveation::kSlopeB);
    EXPECT_DOUBLE_EQ(parseSlope("0.03"), 0.03);
    EXPECT_THROW((void)parseSlope("C"), ArgumentError);
    EXPECT_THROW((void)parseSlope("-0.1"), ArgumentError);
    EXPECT_THROW((void)parseSlope("0.02x"), ArgumentError);
}

TEST(OptionParsing, EveryListedProfileNameIsItsModel) {
    for (const std::string& name : hmdProfileNames()) {
        EXPECT_EQ(hmdProfile(name).name, name);
    }
    EXPECT_EQ(hmdProfileNames().size(), display::kHmdModels.size());
    EXPECT_EQ(parseHmd("rift-cv1"), render::HmdModel::RiftCv1);
    EXPECT_EQ(parseHmd("varjo-xr4"), render::HmdModel::VarjoXr4);
    EXPECT_EQ(parseHmd("vision-pro"), render::HmdModel::VisionPro);
    EXPECT_NE(
        test::thrownMessage<ArgumentError>([] { (void)hmdProfile("oculus-dk9"); }).find("--hmd"),
        std::string::npos);
    for (const std::string& name : displayProfileNames()) {
        EXPECT_EQ(displayProfile(name).name, name);
    }
    EXPECT_EQ(parseDisplay("desktop"), render::DisplayModel::Desktop);
    EXPECT_THROW((void)displayProfile("oculus"), ArgumentError);
}

// --hmd custom:WxH@HFOVxVFOV[,HZ]: the eye image, its field of view split evenly about the axis
// and the refresh; anything else one line that names the value.
TEST(OptionParsing, CustomHmdStrings) {
    // 3840 x 3744 at 120 x 105 degrees, 90 Hz: tangents tan 60 = 1.732051 and
    // tan 52.5 = 1.303225, v = 1 / (2 tan 60) = 0.2886751, ppd = pi 3840 v / 180 = 19.34719.
    const display::HmdProfile xr4 = hmdProfile("custom:3840x3744@120x105,90");
    EXPECT_EQ(xr4.name, "custom:3840x3744@120x105,90");
    EXPECT_EQ(xr4.eyeWidth, 3840u);
    EXPECT_EQ(xr4.eyeHeight, 3744u);
    EXPECT_DOUBLE_EQ(xr4.refreshHz, 90.0);
    EXPECT_NEAR(xr4.tanLeft, -1.732051f, 1e-5f);
    EXPECT_NEAR(xr4.tanRight, 1.732051f, 1e-5f);
    EXPECT_NEAR(xr4.tanUp, 1.303225f, 1e-5f);
    EXPECT_NEAR(xr4.tanDown, -1.303225f, 1e-5f);
    EXPECT_NEAR(xr4.pointSetProfile.viewingDistance, 0.2886751, 1e-7);
    EXPECT_EQ(xr4.pointSetProfile.width, 3840u);
    EXPECT_NEAR(display::centrePixelsPerDegree(xr4), 19.34719, 1e-4);
    EXPECT_GT(xr4.lens.k1, 0.0f); // the published lens
    // Decimal degrees and Hz; the refresh defaults to 90. 640 x 480 at 90 x 73.7398 degrees:
    // tan 45 = 1, tan 36.8699 = 0.75, v = 0.5.
    const display::HmdProfile small = parseCustomHmd("custom:640x480@90x73.7398");
    EXPECT_DOUBLE_EQ(small.refreshHz, 90.0);
    EXPECT_NEAR(small.tanUp, 0.75f, 1e-5f);
    EXPECT_NEAR(small.pointSetProfile.viewingDistance, 0.5, 1e-12);
    EXPECT_DOUBLE_EQ(parseCustomHmd("custom:16x16384@1x169.5,59.94").refreshHz, 59.94);

    // Each bad string: an ArgumentError whose one line names --hmd, the value and what is wrong.
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"custom:", "expected custom:WxH@HFOVxVFOV"},
        {"custom:3840x3744", "expected custom:WxH@HFOVxVFOV"},
        {"custom:3840x3744@120", "expected custom:WxH@HFOVxVFOV"},
        {"custom:3840@120x105", "expected custom:WxH@HFOVxVFOV"},
        {"custom:3840x3744@120x105,", "expected custom:WxH@HFOVxVFOV"},
        {"custom:3840x3744@-120x105", "expected custom:WxH@HFOVxVFOV"},
        {"custom:3840x3744@1e2x105", "expected custom:WxH@HFOVxVFOV"},
        {"custom:3840x3744@120x105,90,1", "expected custom:WxH@HFOVxVFOV"},
        {"custom: 3840x3744@120x105", "expected custom:WxH@HFOVxVFOV"},
        {"custom:15x3744@120x105", "width 15 pixels is outside 16..16384"},
        {"custom:3840x16385@120x105", "height 16385 pixels is outside 16..16384"},
        {"custom:3840x3744@0x105", "horizontal field of view 0 degrees is outside (0, 170)"},
        {"custom:3840x3744@170x105", "horizontal field of view 170 degrees is outside (0, 170)"},
        {"custom:3840x3744@120x180", "vertical field of view 180 degrees is outside (0, 170)"},
        {"custom:3840x3744@120x105,0", "refresh 0 Hz must be above 0"},
        {"custom:3840x3744@120x105,0.0", "refresh 0.0 Hz must be above 0"},
    };
    for (const auto& [text, why] : bad) {
        const std::string& name = text; // a structured binding cannot be captured (clang)
        const std::string m = test::thrownMessage<ArgumentError>([&] { (void)hmdProfile(name); });
        EXPECT_NE(m.find("--hmd " + text + ": " + why), std::string::npos) << text << ": " << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
    // An unknown name lists every choice, the custom syntax included.
    const std::string unknown =
        test::thrownMessage<ArgumentError>([] { (void)hmdProfile("varjo-xr5"); });
    for (const std::string& name : hmdProfileNames())
        EXPECT_NE(unknown.find(name), std::string::npos) << name;
    EXPECT_NE(unknown.find("custom:WxH@HFOVxVFOV[,HZ]"), std::string::npos);
}

TEST(OptionParsing, InterpolationChoices) {
    EXPECT_EQ(parseInterpolation("msm"), render::Interpolation::Shepard);
    EXPECT_EQ(parseView("eccentricity"), render::Interpolation::ViewSpacing);
    EXPECT_EQ(parseView("motion"), render::Interpolation::ViewMotion);
    EXPECT_EQ(parseKernel("gaussian"), render::RbfKernel::Gaussian);
    EXPECT_EQ(parseKnnIndex("lists"), render::KnnIndex::NeighbourLists);
    EXPECT_EQ(parseReconstruction("thesis"), render::Reconstruction::Thesis);
    EXPECT_EQ(parsePresentMode("mailbox"), render::PresentMode::Mailbox);
    EXPECT_NE(test::thrownMessage<ArgumentError>([] {
                  (void)parseInterpolation("idw");
              }).find("--interp"),
              std::string::npos);
    EXPECT_THROW((void)parseView("depth"), ArgumentError);
    EXPECT_THROW((void)parseReconstruction("guenter"), ArgumentError);
}

TEST(OptionParsing, EyeRegionsAndTheGazeReceiver) {
    const auto [left, right] = parseEyeRegions("0,0,320,240;320,0,320,240");
    EXPECT_EQ(left, cv::Rect(0, 0, 320, 240));
    EXPECT_EQ(right, cv::Rect(320, 0, 320, 240));
    EXPECT_THROW((void)parseEyeRegions("0,0,10"), ArgumentError);
    EXPECT_THROW((void)parseEyeRegions("0,0,16,16;320,0,320,240"), ArgumentError);
    const eyetrack::UdpEndpoint to = parseUdpEndpoint("udp://localhost:5005");
    EXPECT_EQ(to.ipv4, "127.0.0.1");
    EXPECT_EQ(to.port, 5005);
    EXPECT_THROW((void)parseUdpEndpoint("tcp://1.2.3.4:5"), ArgumentError);
    EXPECT_THROW((void)parseUdpEndpoint("udp://example.com:5"), ArgumentError);
    EXPECT_THROW((void)parseUdpEndpoint("udp://127.0.0.1:99999"), ArgumentError);
}

TEST(OptionParsing, DeviceRequestIsAnIndexOrANameSubstring) {
    EXPECT_EQ(parseDeviceRequest("1").index, 1u);
    EXPECT_TRUE(parseDeviceRequest("1").nameContains.empty());
    EXPECT_FALSE(parseDeviceRequest("llvmpipe").index.has_value());
    EXPECT_EQ(parseDeviceRequest("llvmpipe").nameContains, "llvmpipe");
    EXPECT_TRUE(parseDeviceRequest("").automatic());
}

// A long number was taken as part of a device's name (or, before that, thrown as "stoul"); a
// negative one as a name too. Both are refused with one line naming the variable.
TEST(OptionParsing, DeviceRequestRefusesIndicesNoMachineHas) {
    for (const char* bad : {"99999999999999999999999", "10000", "-1"}) {
        const std::string message =
            test::thrownMessage<ArgumentError>([&] { (void)parseDeviceRequest(bad); });
        EXPECT_NE(message.find("GAZETRACE_DEVICE=" + std::string(bad)), std::string::npos)
            << message;
    }
    EXPECT_EQ(parseDeviceRequest("9999").index, 9999u);
}

// CLI11 converts "nan", "inf" and "1e400" (infinite as a double) without complaint, and "-5"
// to 2^64 - 5 for a 64-bit unsigned option: every numeric option is checked with these.
TEST(OptionParsing, NumericOptionsMustBeFiniteAndSeedsNotNegative) {
    for (const char* bad : {"nan", "NaN", "inf", "-inf", "1e400", "-1e999", "abc", ""}) {
        EXPECT_FALSE(finiteNumberProblem(bad).empty()) << bad;
    }
    for (const char* good : {"0", "-3.5", "1e30", "0.001"}) {
        EXPECT_EQ(finiteNumberProblem(good), "") << good;
    }
    EXPECT_NE(finiteNumberProblem("nan").find("'nan'"), std::string::npos);
    for (const char* bad : {"-5", " -1", "-0"}) {
        EXPECT_FALSE(nonNegativeIntegerProblem(bad).empty()) << bad;
    }
    EXPECT_EQ(nonNegativeIntegerProblem("42"), "");
}

// sscanf's %d read 4294967328 as 32: eyesim --size 4294967328x240 made a 32-pixel-wide clip.
TEST(OptionParsing, SizesAreDigitsThatFit) {
    EXPECT_EQ(parseSizeText("320x240"), (std::pair<uint32_t, uint32_t>{320, 240}));
    for (const char* bad : {"4294967328x240", "320x-240", "-320x240", " 320x240", "320x", "x240",
                            "320", "320x240x1", "3.5x240"}) {
        EXPECT_FALSE(parseSizeText(bad).has_value()) << bad;
    }
    EXPECT_EQ(parseWholeNumber("4294967295"), 4294967295u);
    EXPECT_FALSE(parseWholeNumber("4294967296").has_value());
}

// Out of memory and a lost device say what to try; other failures stay as they were.
TEST(OptionParsing, VulkanFailuresSayWhatToTry) {
    const VulkanError oom(VK_ERROR_OUT_OF_DEVICE_MEMORY,
                          "allocating the 16384x16384 image 'hdr' (4.0 GiB)", "resources.cpp", 1);
    const std::string m = vulkanFailureMessage(oom);
    EXPECT_EQ(m.rfind("out of GPU memory: allocating the 16384x16384 image 'hdr' (4.0 GiB)", 0), 0u)
        << m;
    EXPECT_NE(m.find("try a smaller --width/--height"), std::string::npos);
    EXPECT_EQ(m.find('\n'), std::string::npos);
    const VulkanError lost(VK_ERROR_DEVICE_LOST, "vkQueueSubmit", "frame.cpp", 1);
    EXPECT_NE(vulkanFailureMessage(lost).find("stopped responding"), std::string::npos);
    const VulkanError host(VK_ERROR_OUT_OF_HOST_MEMORY, "vkCreateBuffer", "resources.cpp", 1);
    EXPECT_EQ(vulkanFailureMessage(host).rfind("out of memory: ", 0), 0u);
    const VulkanError other(VK_ERROR_INITIALIZATION_FAILED, "vkCreateDevice", "context.cpp", 1);
    EXPECT_STREQ(vulkanFailureMessage(other).c_str(), other.what());
}

} // namespace
} // namespace gt::app

namespace gt::app {
namespace {

// GAZETRACE_MAX_TRIANGLES=1e99, -5, 0 or 20M must not be ignored in favour of the default
// limit without a word: a value that is not a whole number from 1 up is refused, naming the
// variable and the value.
TEST(OptionParsing, GltfLimitsFromTheEnvironmentAreParsedStrictly) {
    const auto with = [](const char* name, const char* value) {
        ::setenv(name, value, 1);
        std::string e;
        try {
            (void)gltfLoadOptions();
        } catch (const ArgumentError& x) {
            e = x.what();
        }
        ::unsetenv(name);
        return e;
    };
    for (const char* bad :
         {"abc", "-5", "0", "1e99", "20M", "2e7", "", " 5", "99999999999999999999"}) {
        const std::string e = with("GAZETRACE_MAX_TRIANGLES", bad);
        EXPECT_NE(e.find(std::string("GAZETRACE_MAX_TRIANGLES=") + bad + ":"), std::string::npos)
            << "'" << bad << "': " << e;
    }
    EXPECT_NE(with("GAZETRACE_MAX_INSTANCES", "-1").find("GAZETRACE_MAX_INSTANCES=-1"),
              std::string::npos);
    EXPECT_NE(with("GAZETRACE_MAX_TEXTURE_BYTES", "2G").find("GAZETRACE_MAX_TEXTURE_BYTES=2G"),
              std::string::npos);
    ::setenv("GAZETRACE_MAX_TRIANGLES", "30000000", 1);
    EXPECT_DOUBLE_EQ(gltfLoadOptions().maxTriangles, 3e7);
    ::unsetenv("GAZETRACE_MAX_TRIANGLES");
    EXPECT_DOUBLE_EQ(gltfLoadOptions().maxTriangles, scene::GltfLoadOptions{}.maxTriangles);
}

} // namespace
} // namespace gt::app
