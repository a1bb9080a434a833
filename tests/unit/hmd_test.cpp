// The HMD path's maths without a GPU: profiles, the lens model and its inverse, the stereo rig's
// per-eye gaze, and a window's point-set profile.
#include <cmath>
#include <fstream>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "display/hmd_profile.hpp"
#include "foveation/contrast_sensitivity.hpp"
#include "foveation/eccentricity_layers.hpp"
#include "foveation/gaze_trace.hpp"
#include "foveation/point_set.hpp"
#include "full_resolution.hpp"
#include "gaze/display_geometry.hpp"
#include "gaze_mapping.hpp"
#include "layer_layout.hpp"
#include "stereo_rig.hpp"
#include "support/bad_files.hpp"
#include "support/gpu_test_context.hpp"

namespace gt {
namespace {

TEST(HmdProfile, EveryProfileParsesWithSourcesAndAPlausibleOptics) {
    for (const display::HmdModel model : display::kHmdModels) {
        const display::HmdProfile p = display::hmdProfile(model);
        const std::string& name = p.name;
        EXPECT_FALSE(name.empty());
        EXPECT_GT(p.eyeWidth, 0u);
        EXPECT_FALSE(p.sources.empty()) << name;
        EXPECT_GT(p.pointSetProfile.viewingDistance, 0.0) << name;
        // The left eye's nasal side (right) is never the wider one (vendors that state only a
        // total are split evenly); the right eye mirrors it.
        const auto l = display::eyeTangents(p, 0), r = display::eyeTangents(p, 1);
        EXPECT_LE(l.right, -l.left) << name;
        EXPECT_FLOAT_EQ(r.left, -l.right);
        EXPECT_FLOAT_EQ(r.right, -l.left);
        // So the lens centres sit towards the nose, or at the centre: right of it in the left
        // eye.
        EXPECT_GE(display::lensCentre(l).x, 0.5f);
        EXPECT_LE(display::lensCentre(r).x, 0.5f);
        EXPECT_NEAR(display::lensCentre(l).y, 0.5f, 1e-6f);
        EXPECT_GT(p.ipdM, 0.05f);
        EXPECT_LT(p.ipdM, 0.08f);
    }
}

// Each headset's derived values against values worked out by hand: the tangents of its half
// angles, v of thesis eq. (1) and the pixels per degree at the centre, ppd = pi N v / 180.
TEST(HmdProfile, DerivedValuesMatchTheHandWorkedOnes) {
    // fove: 52 / 48 degrees temporal / nasal, 53 up and down: tan 52 = 1.279942,
    // tan 48 = 1.110613, tan 53 = 1.327045. v stays the fitted 0.85 (Table 1), so
    // ppd = pi * 1280 * 0.85 / 180 = 18.98918.
    const display::HmdProfile fove = display::hmdProfile(display::HmdModel::Fove);
    EXPECT_NEAR(fove.tanLeft, -1.279942f, 1e-5f);
    EXPECT_NEAR(fove.tanRight, 1.110613f, 1e-5f);
    EXPECT_NEAR(fove.tanUp, 1.327045f, 1e-5f);
    EXPECT_NEAR(fove.tanDown, -1.327045f, 1e-5f);
    EXPECT_DOUBLE_EQ(fove.pointSetProfile.viewingDistance, 0.85);
    EXPECT_NEAR(display::centrePixelsPerDegree(fove), 18.98918, 1e-4);
    EXPECT_NEAR(display::horizontalFovDeg(fove), 100.0, 1e-4);

    // varjo-xr4: 120 x 105 degrees split evenly: tan 60 = sqrt 3 = 1.732051, tan 52.5 =
    // 1.303225. v = 1 / (2 tan 60) = 1 / (2 sqrt 3) = 0.2886751, and
    // ppd = pi * 3840 * 0.2886751 / 180 = 19.34719 (the vendor's 51 at the centre come from its
    // lens, which the pinhole model does not have).
    const display::HmdProfile xr4 = display::hmdProfile(display::HmdModel::VarjoXr4);
    EXPECT_EQ(xr4.name, "varjo-xr4");
    EXPECT_EQ(xr4.eyeWidth, 3840u);
    EXPECT_EQ(xr4.eyeHeight, 3744u);
    EXPECT_DOUBLE_EQ(xr4.refreshHz, 90.0);
    EXPECT_NEAR(xr4.tanLeft, -1.732051f, 1e-5f);
    EXPECT_NEAR(xr4.tanRight, 1.732051f, 1e-5f);
    EXPECT_NEAR(xr4.tanUp, 1.303225f, 1e-5f);
    EXPECT_NEAR(xr4.tanDown, -1.303225f, 1e-5f);
    EXPECT_NEAR(xr4.pointSetProfile.viewingDistance, 0.2886751, 1e-7);
    EXPECT_EQ(xr4.pointSetProfile.width, 3840u);
    EXPECT_EQ(xr4.pointSetProfile.height, 3744u);
    EXPECT_NEAR(display::centrePixelsPerDegree(xr4), 19.34719, 1e-4);
    EXPECT_NEAR(display::verticalFovDeg(xr4), 105.0, 1e-4);

    // pimax-crystal: the runtime's frustum, atan 1.264092 + atan 0.889501 = 51.652 + 41.654 =
    // 93.306 degrees; v = 1 / (2 tan 46.653) = 0.4719491, ppd = pi * 2880 * v / 180 = 23.72275.
    const display::HmdProfile pimax = display::hmdProfile(display::HmdModel::PimaxCrystal);
    EXPECT_NEAR(display::horizontalFovDeg(pimax), 93.30625, 1e-3);
    EXPECT_NEAR(pimax.pointSetProfile.viewingDistance, 0.4719491, 1e-6);
    EXPECT_NEAR(display::centrePixelsPerDegree(pimax), 23.72275, 1e-3);

    // A custom 2000 x 1000 eye of 90 x 60 degrees at 75 Hz: tangents tan 45 = 1 and
    // tan 30 = 0.5773503, v = 1 / (2 tan 45) = 0.5, ppd = pi * 2000 * 0.5 / 180 = 17.45329.
    const display::HmdProfile c = display::customHmdProfile("c", 2000, 1000, 90.0, 60.0, 75.0);
    EXPECT_NEAR(c.tanLeft, -1.0f, 1e-6f);
    EXPECT_NEAR(c.tanRight, 1.0f, 1e-6f);
    EXPECT_NEAR(c.tanUp, 0.5773503f, 1e-6f);
    EXPECT_NEAR(c.tanDown, -0.5773503f, 1e-6f);
    EXPECT_NEAR(c.pointSetProfile.viewingDistance, 0.5, 1e-12);
    EXPECT_NEAR(display::centrePixelsPerDegree(c), 17.45329, 1e-4);
    EXPECT_DOUBLE_EQ(c.refreshHz, 75.0);
    EXPECT_THROW((void)display::customHmdProfile("c", 2000, 1000, 90.0, 180.0, 75.0),
                 ArgumentError);
    EXPECT_THROW((void)display::customHmdProfile("c", 0, 1000, 90.0, 60.0, 75.0), ArgumentError);
}

// The thesis's headsets keep their fitted v (their outputs stay as they were); every later one
// takes v = 1 / (2 tan(HFOV / 2)) from its own horizontal field of view.
TEST(HmdProfile, HeadsetsAfterTheThesisTakeVFromTheirFieldOfView) {
    for (const display::HmdModel model : display::kHmdModels) {
        const display::HmdProfile p = display::hmdProfile(model);
        const bool thesisTime = model == display::HmdModel::Fove ||
                                model == display::HmdModel::Vive ||
                                model == display::HmdModel::RiftCv1;
        const double hfov = display::horizontalFovDeg(p) * std::numbers::pi / 180.0;
        const double fromFov = 1.0 / (2.0 * std::tan(0.5 * hfov));
        if (thesisTime) {
            EXPECT_DOUBLE_EQ(p.pointSetProfile.viewingDistance, 0.85) << p.name;
        } else {
            EXPECT_NEAR(p.pointSetProfile.viewingDistance, fromFov, 1e-6) << p.name;
            EXPECT_EQ(p.pointSetProfile.width, p.eyeWidth) << p.name;
            EXPECT_EQ(p.pointSetProfile.height, p.eyeHeight) << p.name;
            EXPECT_GE(p.sources.size(), 4u) << p.name;
        }
        EXPECT_GT(p.refreshHz, 0.0) << p.name;
        EXPECT_GT(p.lens.k1, 0.0f) << p.name; // the published lens, not none
    }
}

// Every headset, and a custom one, through the pieces the HMD path runs, on small inputs: the
// lens (centre inside the image, sourceOf and displayOf inverse), a point set for a small window
// of its display (same pixels per degree), and the eccentricity layers of its frustum.
TEST(HmdProfile, LensPointSetAndLayersWorkForEveryProfile) {
    std::vector<display::HmdProfile> profiles;
    for (const display::HmdModel model : display::kHmdModels)
        profiles.push_back(display::hmdProfile(model));
    profiles.push_back(display::customHmdProfile("custom", 3840, 3744, 120.0, 105.0, 90.0));
    for (const display::HmdProfile& p : profiles) {
        const float aspect = static_cast<float>(p.eyeWidth) / static_cast<float>(p.eyeHeight);
        const display::EyeTangents t = display::eyeTangents(p, 0);
        const glm::vec2 c = display::lensCentre(t);
        EXPECT_GT(c.x, 0.0f) << p.name;
        EXPECT_LT(c.x, 1.0f) << p.name;
        EXPECT_GT(c.y, 0.0f) << p.name;
        EXPECT_LT(c.y, 1.0f) << p.name;
        for (const glm::vec2 q : {glm::vec2(0.0f), glm::vec2(1.0f), glm::vec2(0.3f, 0.8f), c}) {
            const glm::vec2 src = p.lens.sourceOf(q, c, aspect, 1);
            // Barrel: every display point samples the rendered image, inside it.
            EXPECT_GE(src.x, -1e-6f) << p.name;
            EXPECT_LE(src.x, 1.0f + 1e-6f) << p.name;
            const glm::vec2 back = p.lens.displayOf(src, c, aspect);
            EXPECT_NEAR(back.x, q.x, 1e-4f) << p.name;
            EXPECT_NEAR(back.y, q.y, 1e-4f) << p.name;
        }

        // A point set for a 1/16 window of the display (thesis eq. (4) at the display's ppd).
        foveation::PointSetParams params;
        params.display =
            foveation::windowProfile(p.pointSetProfile, p.eyeWidth / 16, p.eyeHeight / 16);
        const foveation::PointSet set = foveation::PointSet::generate(params);
        ASSERT_FALSE(set.points().empty()) << p.name;
        for (const foveation::Point& pt : set.points()) {
            ASSERT_GE(pt.x, 0.0f);
            ASSERT_LT(pt.x, static_cast<float>(set.canvasWidth()));
            ASSERT_GE(pt.y, 0.0f);
            ASSERT_LT(pt.y, static_cast<float>(set.canvasHeight()));
        }
        const float w = static_cast<float>(params.display.width);
        const float h = static_cast<float>(params.display.height);
        const std::size_t onScreen = set.countOnScreen(0.5f * w, 0.5f * h);
        EXPECT_GT(onScreen, 0u) << p.name;

        // The layers of the eye's frustum: three, fewer pixels than the display.
        const trace::FrustumTangents ft{t.left, t.right, t.up, t.down};
        const render::LayerLayout lay = render::layoutLayers(
            p.eyeWidth, p.eyeHeight, render::viewDisplay(p.eyeWidth, p.eyeHeight, ft),
            foveation::MarModel{foveation::kSlopeA}, 3);
        ASSERT_EQ(lay.grids.size(), 3u) << p.name;
        for (const render::LayerGrid& g : lay.grids) {
            EXPECT_GT(g.width, 0u) << p.name;
            EXPECT_GT(g.height, 0u) << p.name;
        }
        EXPECT_LT(lay.pixels(), static_cast<uint64_t>(p.eyeWidth) * p.eyeHeight) << p.name;
    }
}

TEST(LensModel, BarrelMapsTheFarCornerToItselfAndInvertsExactly) {
    const display::LensModel lens = display::hmdProfile(display::HmdModel::Fove).lens;
    const glm::vec2 c(0.52f, 0.5f);
    const float aspect = 1280.0f / 1440.0f;
    // f(1) = 1: the farthest corner samples itself; the centre samples itself.
    const glm::vec2 far(0.0f, 0.0f); // farthest from c (0.52 > 0.5)
    EXPECT_NEAR(glm::length(lens.sourceOf(far, c, aspect, 1) - far), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(lens.sourceOf(c, c, aspect, 1) - c), 0.0f, 1e-7f);
    // Barrel: inside, a display point samples closer to the centre (f < 1).
    const glm::vec2 q(0.8f, 0.3f);
    EXPECT_LT(glm::length(lens.sourceOf(q, c, aspect, 1) - c), glm::length(q - c));
    // Chromatic: red samples nearer the centre than green, blue farther.
    EXPECT_LT(glm::length(lens.sourceOf(q, c, aspect, 0) - c),
              glm::length(lens.sourceOf(q, c, aspect, 1) - c));
    EXPECT_GT(glm::length(lens.sourceOf(q, c, aspect, 2) - c),
              glm::length(lens.sourceOf(q, c, aspect, 1) - c));
    // displayOf inverts sourceOf (green).
    for (const glm::vec2 p : {glm::vec2(0.1f, 0.2f), glm::vec2(0.9f, 0.95f), q}) {
        const glm::vec2 back = lens.displayOf(lens.sourceOf(p, c, aspect, 1), c, aspect);
        EXPECT_NEAR(back.x, p.x, 1e-5f);
        EXPECT_NEAR(back.y, p.y, 1e-5f);
    }
    // The magnification along the radius is the derivative of r f(r).
    const float r = 0.6f, h = 1e-3f;
    EXPECT_NEAR(lens.radialScale(r), ((r + h) * lens.f(r + h) - (r - h) * lens.f(r - h)) / (2 * h),
                1e-3f);
}

TEST(StereoRig, GazeReachesEachEyeThroughItsOwnFrustum) {
    const render::StereoRig rig(display::hmdProfile(display::HmdModel::Fove), true);
    const display::HmdProfile& p = rig.profile();
    // A placeholder method: the rig only stores the pointer.
    struct NoMethod final : render::FoveationMethod {
        std::string_view name() const override { return "none"; }
        render::MethodImage addRadiance(rg::RenderGraph&, const render::View&) override {
            return rg::TextureId{};
        }
        uint64_t rays(const render::View&) const override { return 0; }
        std::optional<render::WarmUp> warmUp(const render::View&) override { return {}; }
    } method;
    scene::Camera head;
    head.position = {0.0f, 1.6f, 0.0f};
    head.forward = {0.0f, 0.0f, -1.0f};
    // Straight ahead at infinity: each eye looks at its lens centre (its optical axis).
    render::StereoGaze ahead;
    const auto v = rig.views(head, ahead, method, {}, 1.0f);
    for (int e = 0; e < 2; ++e) {
        const glm::vec2 centre =
            display::lensCentre(display::eyeTangents(p, e)) * glm::vec2(p.eyeWidth, p.eyeHeight);
        EXPECT_NEAR(v[e].gaze.x, centre.x, 0.01f) << e;
        EXPECT_NEAR(v[e].gaze.y, centre.y, 0.01f) << e;
        ASSERT_TRUE(v[e].post.lens.has_value());
        ASSERT_TRUE(v[e].frustum.has_value());
    }
    EXPECT_NEAR(v[1].camera.position.x - v[0].camera.position.x, p.ipdM, 1e-6f);
    // Converging at 0.5 m: each eye turns inwards by atan(ipd / 2 / 0.5).
    render::StereoGaze near = ahead;
    near.vergenceM = 0.5f;
    const auto w = rig.views(head, near, method, {}, 1.0f);
    for (int e = 0; e < 2; ++e) {
        const auto t = display::eyeTangents(p, e);
        const float tx = t.left + w[e].gaze.x / p.eyeWidth * (t.right - t.left);
        const float expected = (e == 0 ? 1.0f : -1.0f) * 0.5f * p.ipdM / 0.5f;
        EXPECT_NEAR(tx, expected, 1e-4f) << e;
    }
    // A left-eye pixel round-trips through its direction.
    const glm::vec2 px(300.0f, 900.0f);
    const glm::vec3 d = rig.directionOfLeftPixel(px);
    const glm::vec2 back =
        render::pixelOfDirection(d, display::eyeTangents(p, 0), p.eyeWidth, p.eyeHeight);
    EXPECT_NEAR(back.x, px.x, 1e-3f);
    EXPECT_NEAR(back.y, px.y, 1e-3f);
    // Angles as the eye tracker gives them round-trip too.
    const glm::vec2 a = render::anglesOfDirection(render::directionOfAngles({12.0f, -7.5f}));
    EXPECT_NEAR(a.x, 12.0f, 1e-4f);
    EXPECT_NEAR(a.y, -7.5f, 1e-4f);
}

// A window on the desktop screen keeps the screen's pixels per degree.
TEST(WindowProfile, KeepsTheScreensPixelsPerDegree) {
    const foveation::DisplayProfile screen =
        foveation::displayProfile(foveation::DisplayModel::Desktop);
    const foveation::DisplayProfile window = foveation::windowProfile(screen, 640, 360);
    EXPECT_EQ(window.width, 640u);
    EXPECT_NEAR(window.viewingDistance * window.width, screen.viewingDistance * screen.width, 1e-9);
    EXPECT_EQ(foveation::windowProfile(screen, 1920, 1080).name, "desktop");
    EXPECT_NE(window.name, screen.name); // its own point set (the cache keys on the profile)
    // Same eccentricity for the same pixel distance.
    EXPECT_NEAR(
        foveation::ContrastSensitivity::eccentricityDeg(100, window.width, window.viewingDistance),
        foveation::ContrastSensitivity::eccentricityDeg(100, screen.width, screen.viewingDistance),
        1e-9);
}

} // namespace
} // namespace gt

namespace gt {
namespace {

// The tracker's old path put a gaze on the screen as pixels (DisplayGeometry::pixelAtDeg); the
// renderer now takes angles and places them itself. On the desktop profile both must agree.
TEST(GazeMapping, AnglesLandWhereTheTrackersPixelPathPutThem) {
    const render::ScreenGeometry screen;
    const eyetrack::DisplayGeometry old;
    for (const glm::vec2 a : {glm::vec2(0.0f, 0.0f), glm::vec2(10.0f, -5.0f),
                              glm::vec2(-20.0f, 12.0f), glm::vec2(23.0f, 13.0f)}) {
        const glm::vec2 p = screen.pixelOfAngles(a);
        const cv::Point2d q = old.pixelAtDeg({a.x, a.y});
        EXPECT_NEAR(p.x, q.x, 1e-3);
        EXPECT_NEAR(p.y, q.y, 1e-3);
        const glm::vec2 back = screen.anglesOfPixel(p);
        EXPECT_NEAR(back.x, a.x, 1e-4f);
        EXPECT_NEAR(back.y, a.y, 1e-4f);
    }
    // The screen centre straight ahead; a window centred on the screen sees it at its centre.
    const glm::vec2 c =
        screen.pixelOfAngles({0.0f, 0.0f}) - render::centredWindowOrigin(screen, {640, 360});
    EXPECT_NEAR(c.x, 320.0f, 1e-4f);
    EXPECT_NEAR(c.y, 180.0f, 1e-4f);
}

// A single HMD eye: angles through its own projection (tangents), not a screen.
TEST(GazeMapping, AnglesThroughAViewsProjection) {
    render::View v;
    v.width = 1280;
    v.height = 1440;
    v.frustum = trace::FrustumTangents{-1.2f, 1.0f, 1.1f, -1.1f};
    const glm::vec2 ahead = render::pixelOfAnglesInView({0.0f, 0.0f}, v);
    EXPECT_NEAR(ahead.x, 1.2f / 2.2f * 1280.0f, 1e-3f); // the optical axis
    EXPECT_NEAR(ahead.y, 720.0f, 1e-3f);
    const glm::vec2 right = render::pixelOfAnglesInView({45.0f, 0.0f}, v);
    EXPECT_NEAR(right.x, (1.0f + 1.2f) / 2.2f * 1280.0f, 1e-2f); // tan 45 = 1: the right edge
}

TEST(GazeTrace, AngleFormPerEye) {
    const auto dir = test::tempDir("angles");
    const auto file = dir / "angles.csv";
    {
        std::ofstream out(file);
        out << "t_ms,yaw_deg,pitch_deg,eye\n0,1,2,left\n0,3,4,right\n10,5,6,left\n10,7,8,right\n";
    }
    const foveation::GazeTrace t = foveation::GazeTrace::load(file);
    EXPECT_EQ(t.units(), foveation::GazeUnits::AnglesDeg);
    EXPECT_TRUE(t.hasEye(foveation::GazeEye::Left));
    EXPECT_FALSE(t.hasEye(foveation::GazeEye::Both));
    EXPECT_FLOAT_EQ(t.at(5.0, foveation::GazeEye::Left).x, 3.0f);
    EXPECT_FLOAT_EQ(t.at(5.0, foveation::GazeEye::Right).y, 6.0f);
    auto expectBad = [&](const std::string& body, const std::string& mention) {
        test::expectLoadError(dir / "bad.csv", body, mention, [](const std::filesystem::path& f) {
            (void)foveation::GazeTrace::load(f);
        });
    };
    expectBad("t_ms,yaw_deg,pitch_deg,eye\n0,1,2,middle\n", "eye must be");
    expectBad("t_ms,yaw_deg,pitch_deg\n0,95,2\n", "90 degrees");
    expectBad("t_ms,yaw_deg,pitch_deg\n0,1,2\n0,1,2\n", "increase");
    expectBad("t_ms,yaw,pitch\n0,1,2\n", "header");
}

} // namespace
} // namespace gt

#include "display/display_space.hpp"
#include "foveation/point_set.hpp"

namespace gt {
namespace {

// Laying the set on the panel: without a lens it is the image layout; with the barrel lens the
// same points crowd the image's centre and thin its edge.
TEST(DisplaySpace, PanelLayoutFollowsTheLens) {
    foveation::PointSetParams params;
    params.display = {"small-eye", 160, 180, 0.85};
    const foveation::PointSet set = foveation::PointSet::generate(params);
    const glm::vec2 centre(0.5f, 0.5f);
    const glm::vec2 gaze(80.0f, 90.0f);
    display::LensModel none;
    none.k1 = none.k2 = 0.0f;
    const display::LayoutComparison flat = display::compareLayouts(set, gaze, none, centre, 10.0f);
    EXPECT_EQ(flat.imagePoints, flat.panelPoints);
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_NEAR(flat.panelDensity[i], flat.imageDensity[i], 1e-9) << i;
    }
    const display::LensModel lens = display::hmdProfile(display::HmdModel::Fove).lens;
    const display::LayoutComparison barrel =
        display::compareLayouts(set, gaze, lens, centre, 10.0f);
    EXPECT_EQ(barrel.imagePoints, barrel.panelPoints); // gaze on the axis: the same points
    EXPECT_GT(barrel.panelDensity[0], 1.1 * barrel.imageDensity[0]);
    EXPECT_LT(barrel.panelDensity[3], 0.8 * barrel.imageDensity[3]);
    // Each panel point lands where the lens model sends it.
    const auto moved = display::panelPointsInImage(set, gaze, lens, centre, 10.0f);
    ASSERT_EQ(moved.size(), barrel.panelPoints);
}

} // namespace
} // namespace gt
