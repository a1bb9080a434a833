// The OpenXR parts that need no runtime: the session life cycle's decisions, the answer buttons'
// press edges and bindings, and the conversions from what the runtime reports (poses, XrFovf,
// gaze rays) to the renderer's views.
#include <cmath>
#include <map>
#include <set>
#include <string>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "response_actions.hpp"
#include "session_lifecycle.hpp"
#include "xr_error.hpp"
#include "xr_views.hpp"

namespace gt {
namespace {

using xr::LifecycleAction;

TEST(XrLifecycle, BeginsOnReadyEndsOnStoppingExitsOnExiting) {
    xr::SessionLifecycle s;
    EXPECT_EQ(s.onStateChanged(XR_SESSION_STATE_IDLE), LifecycleAction::None);
    EXPECT_FALSE(s.running());
    EXPECT_EQ(s.onStateChanged(XR_SESSION_STATE_READY), LifecycleAction::BeginSession);
    s.began();
    EXPECT_TRUE(s.running());
    EXPECT_EQ(s.onStateChanged(XR_SESSION_STATE_SYNCHRONIZED), LifecycleAction::None);
    EXPECT_EQ(s.onStateChanged(XR_SESSION_STATE_VISIBLE), LifecycleAction::None);
    EXPECT_FALSE(s.focusedOnce());
    EXPECT_EQ(s.onStateChanged(XR_SESSION_STATE_FOCUSED), LifecycleAction::None);
    EXPECT_TRUE(s.focusedOnce());
    s.exitRequested();
    EXPECT_EQ(s.onStateChanged(XR_SESSION_STATE_STOPPING), LifecycleAction::EndSession);
    s.ended();
    EXPECT_FALSE(s.running());
    EXPECT_EQ(s.onStateChanged(XR_SESSION_STATE_IDLE), LifecycleAction::None);
    EXPECT_EQ(s.onStateChanged(XR_SESSION_STATE_EXITING), LifecycleAction::Exit);
    const std::vector<std::string> expected = {"IDLE",    "READY",    "SYNCHRONIZED", "VISIBLE",
                                               "FOCUSED", "STOPPING", "IDLE",         "EXITING"};
    EXPECT_EQ(s.history(), expected);
}

TEST(XrLifecycle, LossPendingIsAnErrorAndReadyAfterStoppingBeginsAgain) {
    xr::SessionLifecycle s;
    ASSERT_EQ(s.onStateChanged(XR_SESSION_STATE_READY), LifecycleAction::BeginSession);
    s.began();
    // The runtime takes the display away (another application) and gives it back.
    ASSERT_EQ(s.onStateChanged(XR_SESSION_STATE_STOPPING), LifecycleAction::EndSession);
    s.ended();
    EXPECT_EQ(s.onStateChanged(XR_SESSION_STATE_READY), LifecycleAction::BeginSession);
    s.began();
    EXPECT_EQ(s.onStateChanged(XR_SESSION_STATE_LOSS_PENDING), LifecycleAction::Lost);
    // A READY while running, or after we asked to leave, begins nothing.
    xr::SessionLifecycle t;
    (void)t.onStateChanged(XR_SESSION_STATE_READY);
    t.began();
    EXPECT_EQ(t.onStateChanged(XR_SESSION_STATE_READY), LifecycleAction::None);
    xr::SessionLifecycle u;
    u.exitRequested();
    EXPECT_EQ(u.onStateChanged(XR_SESSION_STATE_READY), LifecycleAction::None);
    // STOPPING without a begun session ends nothing.
    xr::SessionLifecycle v;
    EXPECT_EQ(v.onStateChanged(XR_SESSION_STATE_STOPPING), LifecycleAction::None);
}

TEST(XrError, NamesTheResultAndSaysWhenTheRuntimeIsGone) {
    EXPECT_EQ(xr::resultName(XR_ERROR_SESSION_LOST), "XR_ERROR_SESSION_LOST");
    EXPECT_EQ(xr::resultName(static_cast<XrResult>(-999999)), "XrResult -999999");
    const xr::XrError gone(XR_ERROR_INSTANCE_LOST, "xrWaitFrame(session, &info, &state)");
    EXPECT_NE(std::string(gone.what())
                  .find("stopped responding (xrWaitFrame: "
                        "XR_ERROR_INSTANCE_LOST)"),
              std::string::npos)
        << gone.what();
    const xr::XrError other(XR_ERROR_VALIDATION_FAILURE, "xrBeginFrame(s, &b)");
    EXPECT_EQ(std::string(other.what()), "OpenXR xrBeginFrame failed: XR_ERROR_VALIDATION_FAILURE");
}

XrFovf fovDeg(float l, float r, float u, float d) {
    return {glm::radians(l), glm::radians(r), glm::radians(u), glm::radians(d)};
}

XrPosef pose(glm::vec3 p, glm::quat q = glm::quat(1, 0, 0, 0)) {
    XrPosef out{};
    out.position = {p.x, p.y, p.z};
    out.orientation = {q.x, q.y, q.z, q.w};
    return out;
}

TEST(XrViews, FovBecomesTangentsAndTheDisplayDistance) {
    const trace::FrustumTangents t = xr::tangentsOfFov(fovDeg(-45, 30, 40, -50));
    EXPECT_NEAR(t.left, -1.0f, 1e-6f);
    EXPECT_NEAR(t.right, std::tan(glm::radians(30.0f)), 1e-6f);
    EXPECT_NEAR(t.up, std::tan(glm::radians(40.0f)), 1e-6f);
    EXPECT_NEAR(t.down, -std::tan(glm::radians(50.0f)), 1e-6f);
    EXPECT_TRUE(t.valid());
    // 90 degrees wide: the image plane at unit distance is 2 wide, so v = 0.5 widths.
    const foveation::DisplayProfile d = xr::eyeDisplay(fovDeg(-45, 45, 45, -45), 640, 640);
    EXPECT_NEAR(d.viewingDistance, 0.5, 1e-6);
    EXPECT_EQ(d.width, 640u);
    // The runtime's field of view, not its tangents' span: -45 to 30 degrees is HFOV = 75, so
    // v = 1 / (2 tan 37.5) = 0.6516127 (1 / (tan 30 + tan 45) would be 0.6339746).
    const foveation::DisplayProfile a = xr::eyeDisplay(fovDeg(-45, 30, 40, -50), 1000, 900);
    EXPECT_NEAR(a.viewingDistance, 0.6516127, 1e-6);
    EXPECT_EQ(a.height, 900u);
}

TEST(XrViews, GazeAheadLandsOnTheAxisAndVergenceShiftsEachEyeInward) {
    const XrFovf fov = fovDeg(-45, 45, 45, -45);
    const glm::vec2 centre = xr::gazePixel({0, 0, -1}, true, pose({-0.032f, 0, 0}), fov, 640, 640);
    EXPECT_NEAR(centre.x, 320.0f, 1e-3f);
    EXPECT_NEAR(centre.y, 320.0f, 1e-3f);
    // A point 0.5 m ahead of the head: the left eye (at -32 mm) sees it right of its axis, the
    // right eye left of it, by atan(0.032 / 0.5) each.
    const glm::vec2 l = xr::gazePixel({0, 0, -0.5f}, false, pose({-0.032f, 0, 0}), fov, 640, 640);
    const glm::vec2 r = xr::gazePixel({0, 0, -0.5f}, false, pose({0.032f, 0, 0}), fov, 640, 640);
    EXPECT_NEAR(l.x - 320.0f, 0.064f * 320.0f, 0.01f);
    EXPECT_NEAR(r.x - 320.0f, -0.064f * 320.0f, 0.01f);
    // Up in the head frame is up the image (smaller y); an off-axis frustum moves the axis.
    const glm::vec2 up = xr::gazePixel({0, 0.2f, -1}, true, pose({0, 0, 0}), fov, 640, 640);
    EXPECT_LT(up.y, 320.0f);
    const glm::vec2 off =
        xr::gazePixel({0, 0, -1}, true, pose({0, 0, 0}), fovDeg(-45, 0, 45, -45), 640, 640);
    EXPECT_NEAR(off.x, 639.0f, 1e-3f); // the axis is the right edge: clamped to the last pixel
    // A pixel and its direction round-trip through a turned eye.
    const XrPosef turned = pose({0, 0, 0}, glm::angleAxis(0.2f, glm::vec3(0, 1, 0)));
    const glm::vec3 dir = xr::directionOfPixel({100.0f, 500.0f}, turned, fov, 640, 640);
    const glm::vec2 back = xr::gazePixel(dir, true, turned, fov, 640, 640);
    EXPECT_NEAR(back.x, 100.0f, 1e-2f);
    EXPECT_NEAR(back.y, 500.0f, 1e-2f);
}

TEST(XrViews, PlacementPutsTheViewerAtTheStartViewFacingItsTarget) {
    scene::Camera start;
    start.position = {2.0f, 1.5f, 3.0f};
    start.forward = glm::normalize(glm::vec3(1.0f, -0.3f, 0.0f)); // looking along +X, down
    const xr::ScenePlacement p = xr::ScenePlacement::facing(start, 2.0f);
    // The head at the origin looking down -Z sees along +X in the scene, level.
    const scene::Camera c = xr::cameraOfPose(pose({0, 0, 0}), p);
    EXPECT_NEAR(glm::distance(c.position, start.position), 0.0f, 1e-5f);
    EXPECT_NEAR(c.forward.x, 1.0f, 1e-5f);
    EXPECT_NEAR(c.forward.y, 0.0f, 1e-5f);
    EXPECT_NEAR(c.up.y, 1.0f, 1e-5f);
    // A step of 1 m to the head's right moves 2 scene units to the scene's -Z... the right of +X.
    const scene::Camera moved = xr::cameraOfPose(pose({1, 0, 0}), p);
    EXPECT_NEAR(moved.position.z - start.position.z, 2.0f, 1e-5f);
    EXPECT_NEAR(moved.position.x - start.position.x, 0.0f, 1e-5f);
    // A head turned 90 degrees left looks along the scene's -Z.
    const scene::Camera left = xr::cameraOfPose(
        pose({0, 0, 0}, glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 1, 0))), p);
    EXPECT_NEAR(left.forward.z, -1.0f, 1e-5f);
}

XrActionStateBoolean buttonState(bool active, bool changed, bool down) {
    XrActionStateBoolean s{XR_TYPE_ACTION_STATE_BOOLEAN};
    s.isActive = active ? XR_TRUE : XR_FALSE;
    s.changedSinceLastSync = changed ? XR_TRUE : XR_FALSE;
    s.currentState = down ? XR_TRUE : XR_FALSE;
    return s;
}

TEST(XrResponseButtons, APressIsReportedOnceOnItsRisingEdge) {
    // A button held over four syncs, then released: down, held, held, up.
    const XrActionStateBoolean frames[] = {
        buttonState(true, true, true), buttonState(true, false, true),
        buttonState(true, false, true), buttonState(true, true, false)};
    int presses = 0;
    for (const auto& f : frames)
        presses += xr::pressBegan(f) ? 1 : 0;
    EXPECT_EQ(presses, 1);
    EXPECT_TRUE(xr::pressBegan(frames[0]));
    EXPECT_FALSE(xr::pressBegan(frames[3])); // a release is no press
    // Inactive (no controller, not focused): nothing, whatever the other fields say.
    EXPECT_FALSE(xr::pressBegan(buttonState(false, true, true)));
}

TEST(XrResponseButtons, EveryButtonIsBoundOnEveryProfileToAHandInput) {
    std::map<std::string, std::set<uint32_t>> buttons;
    std::set<std::pair<std::string, std::string>> seen;
    for (const xr::ButtonBinding& b : xr::ResponseActions::bindings()) {
        const std::string profile(b.profile), path(b.path);
        EXPECT_LT(b.button, xr::ResponseActions::kButtons);
        EXPECT_EQ(profile.rfind("/interaction_profiles/", 0), 0u) << profile;
        EXPECT_TRUE(path.rfind("/user/hand/left/input/", 0) == 0 ||
                    path.rfind("/user/hand/right/input/", 0) == 0)
            << path;
        // Only click and value components: a boolean action reads them as presses.
        EXPECT_TRUE(path.ends_with("/click") || path.ends_with("/value")) << path;
        EXPECT_TRUE(seen.insert({profile, path}).second) << "bound twice: " << path;
        buttons[profile].insert(b.button);
    }
    EXPECT_EQ(buttons.size(), 4u);
    for (const auto& [profile, bound] : buttons) {
        EXPECT_EQ(bound.size(), xr::ResponseActions::kButtons) << profile;
    }
    // The two main answers are the two hands' index fingers on every profile.
    for (const xr::ButtonBinding& b : xr::ResponseActions::bindings()) {
        if (b.button == 0) {
            EXPECT_NE(b.path.find("/left/"), std::string_view::npos) << b.path;
        }
        if (b.button == 1) {
            EXPECT_NE(b.path.find("/right/"), std::string_view::npos) << b.path;
        }
    }
}

} // namespace
} // namespace gt
