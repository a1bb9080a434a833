// `gazetrace xr` against a real OpenXR runtime: Monado, built from ../shared and started
// headless by the CTest fixture (tests/xr/monado_fixture.sh: simulated HMD, null compositor,
// lavapipe). Validation is on in every run; the runtime's own Vulkan calls (its client
// compositor runs in gazetrace's process) are counted apart from gazetrace's.
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <thread>

#include <unistd.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "action_sets.hpp"
#include "core/error.hpp"
#include "eye_gaze.hpp"
#include "foveation/contrast_sensitivity.hpp"
#include "output_target.hpp"
#include "point_set_method.hpp"
#include "renderer.hpp"
#include "response_actions.hpp"
#include "scene/image_io.hpp"
#include "support/cli_run.hpp"
#include "support/gpu_test_context.hpp"
#include "vk/resources.hpp"
#include "xr_eye_fill.hpp"
#include "xr_runtime.hpp"
#include "xr_session.hpp"

namespace gt {
namespace {

using test::Result;

const std::string kRuntimeJson = std::string(GT_MONADO_DIR) + "/build/openxr_monado-dev.json";

// Every gazetrace this binary starts talks to the fixture's service.
const bool kEnvironmentSet = [] {
    setenv("XDG_RUNTIME_DIR", GT_XR_RUNTIME_DIR, 1);
    setenv("XR_RUNTIME_JSON", kRuntimeJson.c_str(), 1);
    return true;
}();

// The fixture's runtime, or empty (the test then skips).
std::string monadoRuntime() {
    if (!std::filesystem::exists(kRuntimeJson) ||
        !std::filesystem::exists(std::filesystem::path(GT_XR_RUNTIME_DIR) / "monado.pid")) {
        return {};
    }
    return kRuntimeJson;
}

#define REQUIRE_MONADO()                                                                           \
    if (monadoRuntime().empty())                                                                   \
    GTEST_SKIP() << "no Monado service: ../shared is absent or the monado fixture did not run"

double meanAbsDiff(const image::DecodedImage& a, const std::vector<uint8_t>& b, glm::vec2 centre,
                   double radius, std::size_t& count) {
    double diff = 0.0;
    count = 0;
    for (uint32_t y = 0; y < a.height; ++y) {
        for (uint32_t x = 0; x < a.width; ++x) {
            if (std::hypot(x - centre.x, y - centre.y) > radius) continue;
            for (int c = 0; c < 3; ++c) {
                const std::size_t i = (static_cast<std::size_t>(y) * a.width + x) * 4 + c;
                diff += std::abs(static_cast<int>(a.rgba[i]) - static_cast<int>(b[i]));
                ++count;
            }
        }
    }
    return count ? diff / static_cast<double>(count) : 0.0;
}

glm::vec3 vec3(const nlohmann::json& j) {
    return {j[0].get<float>(), j[1].get<float>(), j[2].get<float>()};
}

// A private Monado service in its own runtime dir `xdg` (so the fixture's lives on for the other
// tests), `env` set for it (its simulated devices); the service's pid, empty when it failed.
std::string startPrivateMonado(const std::filesystem::path& xdg, const std::string& env) {
    std::filesystem::create_directories(xdg);
    std::filesystem::permissions(xdg, std::filesystem::perms::owner_all);
    const std::string script = std::string(GT_SOURCE_DIR) + "/../shared/tools/monado.sh";
    const auto envFile = xdg.parent_path() / "monado.env";
    if (std::system((env + " XDG_RUNTIME_DIR=" + xdg.string() + " bash " + script + " start " +
                     GT_MONADO_DIR + " > " + envFile.string())
                        .c_str()) != 0) {
        return {};
    }
    std::ifstream in(envFile);
    std::string line, pid;
    while (std::getline(in, line)) {
        if (line.rfind("export MONADO_PID=", 0) == 0) pid = line.substr(18);
    }
    return pid;
}

// Reaches FOCUSED, renders both eyes for N frames with zero validation errors, ends the session
// on --frames; the left eye's image is what a headless render of the pose the runtime reported
// for that frame shows (TAA off: each frame stands alone), with the gaze from --gaze.
void rendersAndMatches(const std::string& eye) {
    const auto dir = test::tempDir("xr_focused_" + eye);
    const auto cache = dir / "cache";
    const auto shot = dir / (eye + ".png");
    const Result r = test::run("xr --frames 4 --validate --json --resolution-scale 0.5 --taa off "
                               "--interp nn --rays-per-point 4 --reconstruction thesis "
                               "--gaze fixed:100,70 --cache " +
                               cache.string() + " --screenshot-eye " + eye + " " + shot.string());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["frames"], 4);
    EXPECT_EQ(j["validation_errors"], 0);
    EXPECT_NE(j["runtime"].get<std::string>().find("Monado"), std::string::npos);
    const auto states = j["session_states"].get<std::vector<std::string>>();
    const auto at = [&](const char* s) {
        return std::find(states.begin(), states.end(), s) - states.begin();
    };
    ASSERT_LT(at("FOCUSED"), static_cast<long>(states.size())) << r.err;
    EXPECT_LT(at("READY"), at("FOCUSED"));
    EXPECT_LT(at("FOCUSED"), at("STOPPING"));
    EXPECT_EQ(states.back(), "EXITING"); // ended cleanly on --frames
    EXPECT_TRUE(j["session_ended_by_runtime"].get<bool>());
    // Monado's simulated HMD has no eye tracker: the fallback is used, and said so.
    EXPECT_EQ(j["gaze_source"], "fixed");
    EXPECT_EQ(j["frames_with_runtime_gaze"], 0);
    for (const char* pass :
         {"left.point_sample", "right.point_sample", "left.xr.blit", "right.xr.blit"}) {
        EXPECT_TRUE(j["gpu_ms"].contains(pass)) << pass;
    }
    for (const auto& e : j["eyes"]) {
        EXPECT_GT(e["width"].get<int>(), 0);
        EXPECT_GT(e["gpu_ms_median"].get<double>(), 0.0);
    }

    // The left eye's last image against the renderer fed the same view headlessly.
    const auto& s = j["screenshot"];
    ASSERT_EQ(s["eye"], eye);
    const uint32_t w = s["width"], h = s["height"];
    const glm::vec2 gaze(s["gaze"][0].get<float>(), s["gaze"][1].get<float>());
    if (eye == "left") {
        EXPECT_NEAR(gaze.x, 100.0f, 0.5f); // --gaze is a pixel of the left eye's image
        EXPECT_NEAR(gaze.y, 70.0f, 0.5f);
    }
    const image::DecodedImage xrImage = image::readPng(shot);
    ASSERT_EQ(xrImage.width, w);
    ASSERT_EQ(xrImage.height, h);

    // The view rebuilt here from what the runtime reported (its pose and XrFovf) and the scene
    // placement gazetrace printed, without gazetrace's own conversion code: the reference
    // space's origin at `origin`, turned by `yaw` about +Y, `scale` scene units per metre.
    const auto& pl = j["placement"];
    const glm::vec3 origin = vec3(pl["origin"]);
    const float yaw = glm::radians(pl["yaw_deg"].get<float>());
    const float scale = pl["scale"].get<float>();
    const glm::mat3 turn = glm::mat3(glm::rotate(glm::mat4(1.0f), yaw, glm::vec3(0, 1, 0)));
    const auto& q = s["xr_pose"]["orientation_xyzw"];
    const glm::quat orientation(q[3].get<float>(), q[0].get<float>(), q[1].get<float>(),
                                q[2].get<float>());
    const auto& fov = s["xr_fov_rad"];
    const trace::FrustumTangents t{std::tan(fov[0].get<float>()), std::tan(fov[1].get<float>()),
                                   std::tan(fov[2].get<float>()), std::tan(fov[3].get<float>())};
    render::View v;
    v.name = eye;
    v.camera.position = origin + turn * (scale * vec3(s["xr_pose"]["position"]));
    v.camera.forward = turn * (orientation * glm::vec3(0, 0, -1));
    v.camera.up = turn * (orientation * glm::vec3(0, 1, 0));
    v.frustum = t;
    v.width = w;
    v.height = h;
    v.gaze = gaze;
    v.post.taa = false;

    render::RendererOptions ro;
    ro.validate = true;
    render::Renderer renderer(ro);
    foveation::PointSetParams params;
    params.display = {"xr", w, h, 1.0 / static_cast<double>(t.right - t.left)};
    render::PointSetMethod method(renderer.methodContext(), params, cache);
    method.settings.raysPerPoint = 4;
    method.settings.interpolation.method = passes::Interpolation::Nearest;
    // The same rays every frame (the thesis's): the xr run's last frame is not its first.
    render::useThesisReconstruction(method.settings, v.post.taaSettings);
    v.method = &method;
    v.exposure = renderer.scene().exposure;
    render::ReadbackTarget target(renderer.context());
    render::OutputTarget* const targets[] = {&target};
    (void)renderer.renderFrame(std::span<const render::View>(&v, 1), targets);
    EXPECT_EQ(renderer.context().validationErrors(), 0u);
    // The fovea: 5 degrees around the gaze at this eye's pixels per degree.
    const double ppd = w / glm::degrees(std::atan(t.right) - std::atan(t.left));
    std::size_t n = 0;
    const double fovea = meanAbsDiff(xrImage, target.pixels(), gaze, 5.0 * ppd, n);
    const std::size_t foveaPixels = n / 3;
    ASSERT_GT(n, 30u);
    EXPECT_LE(fovea, 1.0) << "fovea, " << n / 3 << " pixels";
    const double whole = meanAbsDiff(xrImage, target.pixels(), gaze, 1e9, n);
    EXPECT_LE(whole, 1.0);
    std::printf("xr %s eye against headless: fovea %.4f/255 (%zu px), whole %.4f/255\n",
                eye.c_str(), fovea, foveaPixels, whole);
    // And the image is a picture, not a cleared swapchain.
    double sum = 0.0;
    for (std::size_t i = 0; i < xrImage.rgba.size(); i += 4)
        sum += xrImage.rgba[i];
    EXPECT_GT(sum / (w * h), 10.0);
}

TEST(Xr, RendersBothEyesAndEachMatchesAHeadlessRenderOfItsPose) {
    REQUIRE_MONADO();
    rendersAndMatches("left");
    rendersAndMatches("right");
}

// Eccentricity layers through OpenXR: each eye traces its own layers (from its XrFovf)
// into the runtime's swapchain, validation clean, the session ended cleanly.
TEST(Xr, LayersRenderBothEyes) {
    REQUIRE_MONADO();
    const auto dir = test::tempDir("xr_layers");
    const auto shot = dir / "left.png";
    const Result r = test::run("xr --method layers --slope 0.3 --frames 4 --validate --json "
                               "--resolution-scale 0.5 --gaze fixed:100,70 --screenshot-eye left " +
                               shot.string());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["method"], "layers");
    EXPECT_EQ(j["frames"], 4);
    EXPECT_EQ(j["validation_errors"], 0);
    EXPECT_EQ(j["session_states"].back(), "EXITING");
    for (const char* pass : {"left.layer1.layers.trace", "right.layer1.layers.trace",
                             "left.layers.compose", "right.layers.compose", "right.xr.blit"}) {
        EXPECT_TRUE(j["gpu_ms"].contains(pass)) << pass;
    }
    const image::DecodedImage img = image::readPng(shot);
    EXPECT_GT(img.width, 0u);
}

// An animated glTF through OpenXR: the scene is posed at each frame's predicted display time,
// which advances, with validation clean and the session ended cleanly.
TEST(Xr, AnimatedSceneRunsAtThePredictedDisplayTime) {
    REQUIRE_MONADO();
    const auto start = std::chrono::steady_clock::now();
    const Result r = test::run("xr --scene " GT_SOURCE_DIR
                               "/content/animated/moving_parts.gltf --time 1 --frames 6 "
                               "--validate --json --resolution-scale 0.5 --gaze fixed:100,70");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_TRUE(j["animated"].get<bool>());
    EXPECT_EQ(j["validation_errors"], 0);
    // The last frame's predicted display time is later than the first's (frames take a
    // while on a CPU driver), but no later than the whole run lasted.
    const double runS =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_GT(j["scene_time_s"].get<double>(), 1.0);
    EXPECT_LT(j["scene_time_s"].get<double>(), 1.0 + runS);
    EXPECT_EQ(j["session_states"].back(), "EXITING");
}

// A runtime that exits mid-session (its service killed): a clear one-line error, no hang.
TEST(Xr, RuntimeThatDiesMidSessionEndsWithOneLine) {
    REQUIRE_MONADO();
    const auto dir = test::tempDir("xr_killed");
    // A private service (its own runtime dir), so the shared one lives on for the other tests.
    const auto xdg = dir / "xdg";
    const std::string pid = startPrivateMonado(xdg, "");
    ASSERT_FALSE(pid.empty());
    const auto err = dir / "err.txt";
    const auto status = dir / "status.txt";
    // Endless (--frames 0) until the runtime goes; `timeout` turns a hang into status 124.
    const std::string cmd = "(XDG_RUNTIME_DIR=" + xdg.string() + " timeout 90 " + GT_GAZETRACE_EXE +
                            " xr --resolution-scale 0.25 --cache " + (dir / "cache").string() +
                            " 2> " + err.string() + " > /dev/null; echo $? > " + status.string() +
                            ") &";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    const auto waitFor = [](const std::function<bool()>& done, double seconds) {
        const auto end = std::chrono::steady_clock::now() +
                         std::chrono::milliseconds(static_cast<int>(seconds * 1000));
        while (std::chrono::steady_clock::now() < end) {
            if (done()) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
        return done();
    };
    const bool focused =
        waitFor([&] { return test::slurp(err).find("session FOCUSED") != std::string::npos; }, 60);
    // Let it render a few frames, then kill the service.
    std::this_thread::sleep_for(std::chrono::seconds(2));
    ASSERT_EQ(std::system(("kill -9 " + pid).c_str()), 0);
    ASSERT_TRUE(focused) << test::slurp(err);
    const bool ended = waitFor(
        [&] { return std::filesystem::exists(status) && !test::slurp(status).empty(); }, 95);
    ASSERT_TRUE(ended) << "gazetrace xr did not exit after its runtime died";
    const int code = std::stoi(test::slurp(status));
    EXPECT_NE(code, 124) << "gazetrace xr hung after its runtime died";
    EXPECT_NE(code, 0);
    EXPECT_LT(code, 128) << "gazetrace xr crashed (signal " << code - 128 << ")";
    const std::string text = test::slurp(err);
    const auto last = text.rfind("gazetrace: error:");
    ASSERT_NE(last, std::string::npos) << text;
    const std::string message = text.substr(last);
    EXPECT_EQ(test::lines(message), 1) << message;
    EXPECT_NE(message.find("OpenXR runtime"), std::string::npos) << message;
}

// An eye's swapchain image read back (RGBA or BGRA bytes as the format has them); it stays in
// COLOR_ATTACHMENT_OPTIMAL, as OpenXR wants it released.
std::vector<uint8_t> readEye(vk::Context& ctx, const xr::EyeImage& img) {
    const VkDeviceSize bytes = VkDeviceSize(img.extent.width) * img.extent.height * 4;
    vk::Buffer buffer(ctx, {bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUsage::Readback,
                            "test.eye_readback"});
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
        b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
        b.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        b.oldLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        b.newLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
        b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        b.image = img.image;
        b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                             VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0, nullptr, 1, &b);
        VkBufferImageCopy c{};
        c.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        c.imageExtent = {img.extent.width, img.extent.height, 1};
        vkCmdCopyImageToBuffer(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                               buffer.handle(), 1, &c);
        std::swap(b.oldLayout, b.newLayout);
        b.srcAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        b.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0, 0, nullptr, 0,
                             nullptr, 1, &b);
    });
    std::vector<uint8_t> px(bytes);
    buffer.download(std::as_writable_bytes(std::span(px)));
    return px;
}

using EyePixels = std::array<std::pair<std::vector<uint8_t>, VkExtent2D>, 2>;

// The fixation frame as written: in the left eye white on the arms and centre of the cross at
// (40, 30) with arms of 6 pixels, black elsewhere; the right eye black.
void expectFixationFrame(const EyePixels& eyes) {
    const auto at = [&](uint32_t e, uint32_t x, uint32_t y) {
        return eyes[e].first.at((static_cast<std::size_t>(y) * eyes[e].second.width + x) * 4);
    };
    ASSERT_FALSE(eyes[0].first.empty());
    ASSERT_GE(eyes[0].second.width, 60u);
    EXPECT_EQ(at(0, 40, 30), 255);
    EXPECT_EQ(at(0, 46, 30), 255); // the arm's end
    EXPECT_EQ(at(0, 40, 24), 255);
    EXPECT_EQ(at(0, 47, 30), 0); // past it
    EXPECT_EQ(at(0, 44, 34), 0); // between the arms
    EXPECT_EQ(at(0, 0, 0), 0);
    for (std::size_t i = 0; i < eyes[1].first.size(); i += 4)
        ASSERT_EQ(eyes[1].first[i], 0) << i / 4;
}

// The answer buttons and eye gaze in one session: their action sets attached in one call (a
// second xrAttachSessionActionSets would fail), every set synced once a frame, and no press
// reported while nobody touches a controller. Each frame is a study's fixation frame (EyeFill),
// submitted to the runtime and read back once. A private service with Monado's simulated simple
// controllers in both hands, so the buttons are bound (and read from a synced set).
TEST(XrActions, ButtonsAndEyeGazeAttachTogetherSyncEveryFrameAndReportNoPress) {
    REQUIRE_MONADO();
    // A short path: the service's socket path must fit a sockaddr_un (108 bytes).
    const auto xdg = std::filesystem::temp_directory_path() /
                     ("gt_xr_actions_" + std::to_string(getpid())) / "xdg";
    const std::string pid = startPrivateMonado(xdg, "SIMULATED_LEFT=simple SIMULATED_RIGHT=simple");
    ASSERT_FALSE(pid.empty());
    struct Restore {
        std::string pid;
        std::filesystem::path xdg;
        ~Restore() {
            setenv("XDG_RUNTIME_DIR", GT_XR_RUNTIME_DIR, 1);
            (void)std::system(("kill " + pid).c_str());
            std::filesystem::remove_all(xdg.parent_path());
        }
    } restore{pid, xdg};
    setenv("XDG_RUNTIME_DIR", xdg.c_str(), 1); // the in-process client connects here
    xr::RuntimeOptions rto;
    rto.runtimeManifest = monadoRuntime();
    xr::Runtime runtime(rto);
    render::RendererOptions ro;
    ro.validate = true;
    ro.framesInFlight = 1;
    ro.display = runtime.vulkanHooks();
    render::Renderer renderer(ro);
    xr::Session session(runtime, renderer.context(), xr::SessionOptions{false, 0.25});
    {
        xr::ActionSets sets(session);
        // Monado offers the extension without an eye tracker: its binding is still suggested.
        ASSERT_TRUE(runtime.eyeGazeOffered());
        xr::EyeGaze gaze(sets);
        xr::ResponseActions buttons(sets);
        sets.attach();
        sets.attach(); // once per session: a second call does nothing
        EXPECT_TRUE(sets.attached());
        EXPECT_EQ(sets.setCount(), 2u);
        EXPECT_THROW((void)sets.createSet("late", "late"), Error);
        const auto& suggested = sets.suggestedProfiles();
        for (const char* profile : {"/interaction_profiles/khr/simple_controller",
                                    "/interaction_profiles/ext/eye_gaze_interaction"}) {
            EXPECT_NE(std::find(suggested.begin(), suggested.end(), profile), suggested.end())
                << profile;
        }

        uint32_t frames = 0, focusedFrames = 0, maxActive = 0;
        app::EyeFill fill(renderer.context());
        EyePixels eyes;
        const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        while (session.pollEvents() && std::chrono::steady_clock::now() < end) {
            if (!session.running()) {
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
                continue;
            }
            const xr::FrameInfo frame = session.beginFrame();
            const bool focused = sets.syncs() == frames && sets.sync();
            ++frames;
            focusedFrames += focused ? 1 : 0;
            EXPECT_TRUE(buttons.pressed().empty());
            maxActive = std::max(maxActive, buttons.activeButtons());
            (void)gaze.locate(frame.displayTime);
            // A fixation frame: the left eye black with a cross at (40, 30), the right black.
            for (uint32_t e = 0; e < 2 && frame.shouldRender; ++e) {
                const xr::EyeImage img = session.acquire(e);
                const std::optional<app::FixationCross> cross =
                    e == 0 ? std::optional(app::FixationCross{{40.0f, 30.0f}, 6, 2}) : std::nullopt;
                fill.fill({img.image, img.format, img.extent, 0}, cross);
                if (focusedFrames == 20) eyes[e] = {readEye(renderer.context(), img), img.extent};
                session.release(e);
            }
            session.endFrame(frame, frame.shouldRender);
            if (focusedFrames == 20 && !session.lifecycle().isExitRequested()) {
                session.requestExit();
            }
        }
        EXPECT_EQ(session.lifecycle().history().back(), "EXITING");
        EXPECT_GE(focusedFrames, 20u);
        EXPECT_EQ(sets.syncs(), frames); // one xrSyncActions a frame, both sets in it
        EXPECT_EQ(sets.focusedSyncs(), focusedFrames);
        EXPECT_EQ(buttons.presses(), 0u);
        // The simple controllers' select and menu: every button, through the synced set.
        EXPECT_EQ(maxActive, xr::ResponseActions::kButtons);

        expectFixationFrame(eyes);
    }
    EXPECT_EQ(renderer.context().validationErrors(), 0u);
}

// A perception study in the headset: two trials of a forced choice on the point-set scale,
// one on each of two scenes (both on the runtime's device), answered by a simulated observer
// (Monado gives no button presses), every stimulus of both scenes built for the runtime's eye
// images first, each trial journaled with its scene and its intervals' frames. The buttons'
// action set is synced on every frame the runtime paced, bound to Monado's simulated simple
// controllers, and reported no press.
TEST(XrStudy, AShortRunInTheHeadsetJournalsItsTrials) {
    REQUIRE_MONADO();
    // Its own service with simulated controllers, so the buttons are bound (a short path: the
    // socket's must fit a sockaddr_un).
    const auto xdg = std::filesystem::temp_directory_path() /
                     ("gt_xr_study_" + std::to_string(getpid())) / "xdg";
    const std::string pid = startPrivateMonado(xdg, "SIMULATED_LEFT=simple SIMULATED_RIGHT=simple");
    ASSERT_FALSE(pid.empty());
    struct Stop {
        std::string pid;
        std::filesystem::path xdg;
        ~Stop() {
            (void)std::system(("kill " + pid).c_str());
            std::filesystem::remove_all(xdg.parent_path());
        }
    } stop{pid, xdg};
    const auto dir = test::tempDir("xr_study");
    const auto design = dir / "design.json";
    std::ofstream(design) << R"({
        "name": "xr_tiny", "procedure": "forced-choice", "seed": 11,
        "width": 160, "height": 120,
        "timing": {"fixation_ms": 50, "interval_ms": 100, "blank_ms": 50},
        "scenes": [{"scene": "builtin:market"}, {"scene": "builtin:cornell"}],
        "conditions": [{"name": "scale", "vary": "scale",
                        "levels": {"min": 1.0, "max": 2.0, "step": 1.0},
                        "placement": {"kind": "staircase", "max_trials": 4}}]
    })";
    const auto journal = dir / "journal.jsonl";
    // `timeout` turns a run that never ends its trials into status 124.
    // --foreground: timeout signals gazetrace alone; without it, it signals its process group
    // too, and a second SIGINT arriving after the first was handled kills the run (exit 130).
    const Result r = test::runWith("env XDG_RUNTIME_DIR=" + xdg.string() + " timeout 300",
                                   "study --display xr --validate --design " + design.string() +
                                       " --participant P01 --journal " + journal.string() +
                                       " --observer level:1.5 --max-trials 2 --cache " +
                                       (dir / "cache").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["display"], "xr");
    EXPECT_NE(j["runtime"].get<std::string>().find("Monado"), std::string::npos);
    EXPECT_EQ(j["trials_done"], 2);
    EXPECT_EQ(j["trials_journaled"], 2);
    EXPECT_EQ(j["validation_errors"], 0);
    EXPECT_EQ(j["session_states"].back(), "EXITING");
    EXPECT_LE(j["eye"][0].get<int>(), 160); // fitted into the design's view
    EXPECT_LE(j["eye"][1].get<int>(), 120);
    EXPECT_GT(j["frames_stimulus"].get<int>(), 0);
    EXPECT_GT(j["frames_fixation"].get<int>(), 0);
    EXPECT_GT(j["frames_blank"].get<int>(), 0);
    const auto& a = j["responses"];
    // One xrSyncActions on every frame the runtime paced, shown or not.
    EXPECT_EQ(a["syncs"].get<int>(), j["frames"].get<int>() + j["frames_not_shown"].get<int>());
    EXPECT_GT(a["focused_syncs"].get<int>(), 0);
    EXPECT_EQ(a["buttons_bound"], 4); // read from the synced set on the controllers
    EXPECT_EQ(a["button_presses"], 0);
    EXPECT_EQ(a["button_answers"], 0);
    EXPECT_GE(a["observer_answers"].get<int>(), 2);
    const auto profiles = a["profiles"].get<std::vector<std::string>>();
    EXPECT_NE(
        std::find(profiles.begin(), profiles.end(), "/interaction_profiles/khr/simple_controller"),
        profiles.end());
    for (const char* scene : {"builtin:market", "builtin:cornell"}) {
        EXPECT_FALSE(j["stimuli"][scene].empty()) << j["stimuli"];
    }

    // The journal: both trials, one per scene, each interval's frames counted, answered first
    // or second.
    std::ifstream in(journal);
    int trials = 0;
    std::vector<int> scenes;
    for (std::string line; std::getline(in, line);) {
        const auto t = nlohmann::json::parse(line);
        if (t.value("type", "") != "trial") continue;
        ++trials;
        scenes.push_back(t["scene"].get<int>());
        const std::string response = t["response"];
        EXPECT_TRUE(response == "first" || response == "second") << line;
        ASSERT_EQ(t["intervals"].size(), 2u) << line;
        for (const auto& interval : t["intervals"]) {
            EXPECT_GT(interval["frames"].get<int>(), 0) << line;
            // The frame clock is the runtime's display time: an interval never holds more
            // frames than its length at the display's refresh.
            EXPECT_LE(interval["frames"].get<int>(), interval["expected_frames"].get<int>())
                << line;
        }
    }
    EXPECT_EQ(trials, 2);
    std::sort(scenes.begin(), scenes.end());
    EXPECT_EQ(scenes, (std::vector<int>{0, 1}));
}

// SIGINT during a study in the headset: the runtime is asked to end the session, which ends
// cleanly; every trial answered so far is journaled, and the summary says the run ended early.
TEST(XrStudy, SigintEndsTheSessionWithItsJournalComplete) {
    REQUIRE_MONADO();
    const auto dir = test::tempDir("xr_study_sigint");
    const auto design = dir / "design.json";
    std::ofstream(design) << R"({
        "name": "xr_long", "procedure": "forced-choice", "seed": 5,
        "width": 160, "height": 120,
        "timing": {"fixation_ms": 200, "interval_ms": 500, "blank_ms": 200},
        "conditions": [{"name": "scale", "vary": "scale",
                        "levels": {"min": 1.0, "max": 2.0, "step": 1.0},
                        "placement": {"kind": "staircase", "max_trials": 400}}]
    })";
    const auto journal = dir / "journal.jsonl";
    // SIGINT once the first trial is journaled: after a fixed 10 s, a loaded machine had not
    // finished one yet.
    const Result r = test::runInterruptedWhen(
        "",
        "study --display xr --design " + design.string() + " --participant P01 --journal " +
            journal.string() + " --observer level:1.5 --cache " + (dir / "cache").string(),
        journal, "\"type\":\"trial\"", 300);
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_TRUE(j["ended_early"].get<bool>());
    EXPECT_FALSE(j["finished"].get<bool>());
    EXPECT_EQ(j["session_states"].back(), "EXITING");
    std::ifstream in(journal);
    int trials = 0;
    for (std::string line; std::getline(in, line);) {
        trials += nlohmann::json::parse(line).value("type", "") == "trial" ? 1 : 0;
    }
    EXPECT_GT(trials, 0);
    EXPECT_EQ(j["trials_journaled"], trials);
    EXPECT_EQ(j["trials_done"], trials);
}

// No runtime, or a runtime whose service is not running: one line naming the problem and what
// to install or set.
TEST(Xr, MissingRuntimeIsOneLine) {
    const auto dir = test::tempDir("xr_missing");
    const auto shot = dir / "never.png";
    const Result r = test::runWith("env XR_RUNTIME_JSON=" + (dir / "no_runtime.json").string(),
                                   "xr --frames 2 --screenshot-eye left " + shot.string());
    test::expectCleanFailure(r, "XR_RUNTIME_JSON", shot);
    EXPECT_NE(r.err.find("no OpenXR runtime"), std::string::npos) << r.err;
}

TEST(Xr, RuntimeWithoutVulkanIsOneLine) {
    const auto dir = test::tempDir("xr_novulkan");
    const auto manifest = dir / "fake_runtime.json";
    {
        std::ofstream out(manifest);
        out << R"({"file_format_version": "1.0.0", "runtime": {"name": "fake", "library_path": ")"
            << GT_FAKE_XR_RUNTIME << "\"}}\n";
    }
    const auto shot = dir / "never.png";
    const Result r = test::runWith("env XR_RUNTIME_JSON=" + manifest.string(),
                                   "xr --frames 2 --screenshot-eye left " + shot.string());
    test::expectCleanFailure(r, "XR_KHR_vulkan_enable2", shot);
    EXPECT_NE(r.err.find("XR_RUNTIME_JSON"), std::string::npos) << r.err;
}

TEST(Xr, RuntimeWithoutItsServiceIsOneLine) {
    REQUIRE_MONADO();
    const auto dir = test::tempDir("xr_noservice");
    const auto xdg = dir / "empty_xdg";
    std::filesystem::create_directories(xdg);
    const auto shot = dir / "never.png";
    const Result r = test::runWith("env XDG_RUNTIME_DIR=" + xdg.string(),
                                   "xr --frames 2 --screenshot-eye left " + shot.string());
    // Monado prints its own lines about the missing service first; gazetrace's is the last one.
    EXPECT_NE(r.status, 0);
    const auto last = r.err.rfind("gazetrace: error:");
    ASSERT_NE(last, std::string::npos) << r.err;
    const std::string message = r.err.substr(last);
    EXPECT_EQ(test::lines(message), 1) << message;
    EXPECT_NE(message.find("service is running"), std::string::npos) << message;
    EXPECT_FALSE(std::filesystem::exists(shot));
}

TEST(Xr, BadOptionsFailBeforeTheRuntime) {
    const auto dir = test::tempDir("xr_badargs");
    const auto shot = dir / "never.png";
    test::expectCleanFailure(test::run("xr --xr-space moon"), "--xr-space", shot);
    test::expectCleanFailure(test::run("xr --xr-origin 1,2"), "--xr-origin", shot);
    test::expectCleanFailure(test::run("xr --xr-scale 0"), "--xr-scale", shot);
    test::expectCleanFailure(
        test::run("xr --screenshot-eye middle " + shot.string() + " --frames 1"),
        "--screenshot-eye", shot);
    test::expectCleanFailure(test::run("xr --screenshot-eye left " + shot.string()), "--frames",
                             shot);
    test::expectCleanFailure(test::run("xr --gaze nonsense"), "--gaze", shot);
}

} // namespace
} // namespace gt
