// Eccentricity layers (Guenter et al. 2012) on lavapipe with validation on: the blend masks of
// Figure 3, the half-rate schedule, a static scene converging without seams at the layer borders,
// resets.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include "eccentricity_layers.hpp"
#include "full_resolution.hpp"
#include "layers/layers.hpp"
#include "output_target.hpp"
#include "readback/readback.hpp"
#include "renderer.hpp"
#include "support/gpu_test_context.hpp"
#include "support/graph_fill.hpp"
#include "support/image_diff.hpp"
#include "vk/resources.hpp"

namespace gt {
namespace {

// ---------------------------------------------------------------------------------------------
// The compose step alone: layers of constant colour, read back as floats.

class LayersComposeTest : public test::GpuTest {
protected:
    static constexpr uint32_t kSize = 96;

    // Three full-display layers, pure red (inner), green (middle), blue (outer), composed around
    // the display centre with radii 16 and 36; `middleOrigin` moves the middle layer's grid.
    std::vector<glm::vec4> compose(glm::vec2 middleOrigin = {}, uint32_t middleWidth = kSize) {
        const passes::LayersPass pass(ctx());
        rg::RenderGraph g(kSize, kSize);
        auto fill = [&](const char* name, uint32_t w, glm::vec4 c) {
            return test::addFilledTexture(g, name,
                                          {VK_FORMAT_R32G32B32A32_SFLOAT, rg::SizeMode::Absolute,
                                           static_cast<float>(w), kSize},
                                          c);
        };
        const std::array<passes::ComposedLayer, 3> layers{
            passes::ComposedLayer{fill("inner", kSize, {1, 0, 0, 1}), {}, 1.0f, 16.0f},
            passes::ComposedLayer{fill("middle", middleWidth, {0, 1, 0, 1}), middleOrigin, 1.0f,
                                  36.0f},
            passes::ComposedLayer{fill("outer", kSize, {0, 0, 1, 1}), {}, 1.0f, 0.0f}};
        const rg::TextureId out = pass.addCompose(g, layers, glm::vec2(48.0f), 0.4f);
        vk::Buffer host(ctx(),
                        {VkDeviceSize{kSize} * kSize * 16, 0, vk::MemoryUsage::Readback, "host"});
        const auto hostId = g.importBuffer(
            "host", {host.handle(), host.size(), std::nullopt, rg::Access::HostRead});
        passes::addReadbackPass(g, "composed", out, hostId);
        rg::TransientPool pool(ctx());
        (void)g.executeAndWait(g.compile(), pool);
        std::vector<glm::vec4> px(std::size_t{kSize} * kSize);
        host.download(std::as_writable_bytes(std::span(px)));
        return px;
    }
    static float distance(uint32_t x, uint32_t y) {
        return glm::length(glm::vec2(static_cast<float>(x), static_cast<float>(y)) - 48.0f);
    }
};

TEST_F(LayersComposeTest, MasksSumToOneAndFollowFigureThree) {
    const std::vector<glm::vec4> px = compose();
    auto smooth = [](float e0, float e1, float x) {
        const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
        return t * t * (3.0f - 2.0f * t);
    };
    for (uint32_t y = 0; y < kSize; ++y) {
        for (uint32_t x = 0; x < kSize; ++x) {
            const glm::vec4 c = px[y * kSize + x];
            const float d = distance(x, y);
            ASSERT_NEAR(c.r + c.g + c.b, 1.0f, 1e-5f) << x << "," << y;
            // Inner weight: 1 inside 0.6 r, 0 beyond r = 16, smoothstep between (Figure 3).
            const float inner = 1.0f - smooth(9.6f, 16.0f, d);
            const float middle = (1.0f - inner) * (1.0f - smooth(21.6f, 36.0f, d));
            ASSERT_NEAR(c.r, inner, 1e-5f) << x << "," << y;
            ASSERT_NEAR(c.g, middle, 1e-5f) << x << "," << y;
        }
    }
    EXPECT_EQ(px[48 * kSize + 48], glm::vec4(1, 0, 0, 1));      // the gaze: inner only
    EXPECT_EQ(px[48 * kSize + 48 + 18], glm::vec4(0, 1, 0, 1)); // 18 px out: middle only
    EXPECT_EQ(px[0], glm::vec4(0, 0, 1, 1));                    // the corner: outer only
}

TEST_F(LayersComposeTest, PixelsALayerDoesNotCoverShowTheLayerOutside) {
    // The middle layer covers only x < 40 (a half-rate layer still around last frame's gaze).
    const std::vector<glm::vec4> px = compose({}, 40);
    const glm::vec4 left = px[48 * kSize + 48 - 18], right = px[48 * kSize + 48 + 18];
    EXPECT_EQ(left, glm::vec4(0, 1, 0, 1));
    EXPECT_EQ(right, glm::vec4(0, 0, 1, 1));
    for (const glm::vec4& c : px) {
        ASSERT_NEAR(c.r + c.g + c.b, 1.0f, 1e-5f);
    }
}

// ---------------------------------------------------------------------------------------------
// The method in the renderer.

class EccentricityLayersTest : public ::testing::Test {
protected:
    static constexpr uint32_t kW = 240, kH = 144;
    static void SetUpTestSuite() {
        sRenderer = std::make_unique<render::Renderer>(
            render::RendererOptions{.scene = "builtin:market", .validate = true});
    }
    static void TearDownTestSuite() { sRenderer.reset(); }
    void SetUp() override { mErrorsBefore = renderer().context().validationErrors(); }
    void TearDown() override {
        EXPECT_EQ(renderer().context().validationErrors(), mErrorsBefore)
            << (renderer().context().validationMessages().empty()
                    ? std::string()
                    : renderer().context().validationMessages().back());
    }
    static render::Renderer& renderer() { return *sRenderer; }

    // A slope steep enough that a 240-pixel view (1.2 deg per pixel pair) has coarser layers:
    // the paper allows any slope, and A or B would keep every layer at the display's pitch here.
    static render::EccentricityLayerSettings settings() {
        render::EccentricityLayerSettings s;
        s.slope = 0.25;
        return s;
    }
    static render::View view(render::FoveationMethod& method, const std::string& name = "") {
        render::View v;
        v.name = name;
        v.camera = renderer().scene().camera;
        v.width = kW;
        v.height = kH;
        v.gaze = {0.5f * kW, 0.5f * kH};
        v.method = &method;
        v.post.taa = false;
        return v;
    }
    static std::vector<uint8_t> frame(const render::View& v,
                                      render::FrameResult* result = nullptr) {
        render::ReadbackTarget readback(renderer().context());
        render::OutputTarget* const target = &readback;
        const render::FrameResult f =
            renderer().renderFrame(std::span(&v, 1), std::span(&target, 1));
        if (result) {
            *result = f;
        }
        return readback.takePixels();
    }
    static scene::Camera sideCamera() {
        const scene::Camera c = renderer().scene().camera;
        return scene::lookAt(c.position, {5.0f, 1.5f, 5.0f}, c.yfov);
    }
    static double meanAbsDiff(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
        return test::meanAbsDiff(a, b);
    }
    inline static std::unique_ptr<render::Renderer> sRenderer;

private:
    uint32_t mErrorsBefore = 0;
};

TEST_F(EccentricityLayersTest, LayoutFollowsTheModel) {
    render::EccentricityLayers layers(renderer().methodContext(), settings());
    const render::View v = view(layers);
    const render::LayerLayout& lay = layers.layout(v);
    ASSERT_EQ(lay.grids.size(), 3u);
    EXPECT_FLOAT_EQ(lay.grids[0].pitch, 1.0f);
    EXPECT_GT(lay.grids[1].pitch, 1.5f);
    EXPECT_GT(lay.grids[2].pitch, lay.grids[1].pitch);
    EXPECT_TRUE(lay.grids[2].outer);
    EXPECT_EQ(lay.grids[2].width, static_cast<uint32_t>(std::ceil(kW / lay.grids[2].pitch)));
    EXPECT_LT(lay.pixels(), static_cast<uint64_t>(kW) * kH);
}

TEST_F(EccentricityLayersTest, OuterLayersRunAtHalfRateStaggered) {
    render::EccentricityLayers layers(renderer().methodContext(), settings());
    render::View v = view(layers, "halfrate");
    const render::LayerLayout lay = layers.layout(v);
    auto pixels = [&](std::size_t i) {
        return static_cast<uint64_t>(lay.grids[i].width) * lay.grids[i].height;
    };
    std::vector<std::vector<bool>> traced;
    std::vector<uint64_t> rays;
    for (int i = 0; i < 5; ++i) {
        render::FrameResult f;
        (void)frame(v, &f);
        traced.push_back(layers.tracedLastFrame(v));
        rays.push_back(f.views[0].rays);
    }
    EXPECT_EQ(traced[0], (std::vector<bool>{true, true, true})); // no history yet
    EXPECT_EQ(traced[1], (std::vector<bool>{true, true, false}));
    EXPECT_EQ(traced[2], (std::vector<bool>{true, false, true}));
    EXPECT_EQ(traced[3], (std::vector<bool>{true, true, false}));
    EXPECT_EQ(rays[0], pixels(0) + pixels(1) + pixels(2));
    // Two consecutive frames: the inner layer twice, the others once each.
    EXPECT_EQ(rays[2] + rays[3], 2 * pixels(0) + pixels(1) + pixels(2));
    // A saccade re-traces every layer around the new gaze at once.
    v.saccade = true;
    v.gaze = {30.0f, 30.0f};
    (void)frame(v);
    EXPECT_EQ(layers.tracedLastFrame(v), (std::vector<bool>{true, true, true}));
    // So does a reset of the view's history.
    v.saccade = false;
    (void)frame(v);
    renderer().resetHistory("halfrate");
    (void)frame(v);
    EXPECT_EQ(layers.tracedLastFrame(v), (std::vector<bool>{true, true, true}));
}

// A resized view retraces every layer at once: a half-rate layer on its off frame must not read a
// history the new size replaced (it would compose uninitialised texels).
TEST_F(EccentricityLayersTest, ResizeRetracesEveryLayer) {
    render::EccentricityLayers layers(renderer().methodContext(), settings());
    render::View v = view(layers, "resize");
    for (int i = 0; i < 2; ++i) {
        (void)frame(v);
    }
    ASSERT_EQ(layers.tracedLastFrame(v), (std::vector<bool>{true, true, false}));
    v.width = 200; // the gaze stays where it was: no saccade resets the layers
    v.height = 120;
    (void)frame(v);
    EXPECT_EQ(layers.tracedLastFrame(v), (std::vector<bool>{true, true, true}));
}

// A still view converges: one jittered ray per layer pixel a frame, averaged in each layer's
// history, approaches what 16 stratified rays per layer pixel give in one frame (the layer's
// box-filtered, supersampled image). Linear radiance averages slowly around highlights, so the
// bound is on the error, not on a frame-to-frame change.
TEST_F(EccentricityLayersTest, StaticSceneConverges) {
    render::EccentricityLayerSettings limitSettings = settings();
    limitSettings.raysPerPixel = 16;
    limitSettings.jitter = false;
    limitSettings.temporal = false;
    render::EccentricityLayers limitMethod(renderer().methodContext(), limitSettings);
    render::View limitView = view(limitMethod, "limit");
    limitView.camera = sideCamera();
    const std::vector<uint8_t> limit = frame(limitView);
    render::EccentricityLayers layers(renderer().methodContext(), settings());
    render::View v = view(layers, "converging");
    v.camera = sideCamera();
    const double first = meanAbsDiff(frame(v), limit);
    std::vector<uint8_t> last;
    for (int i = 1; i < 32; ++i) {
        last = frame(v);
    }
    const double converged = meanAbsDiff(last, limit);
    EXPECT_LT(converged, 0.6 * first) << "first " << first << ", after 32 frames " << converged;
    std::printf("to the 16-ray layers: first frame %.2f/255, after 32 frames %.2f/255\n", first,
                converged);
}

// With every layer at the display's pitch and no jitter or history, three blended layers must
// give exactly what one layer gives: any misregistration between layers or gap in the masks
// would show as a difference.
TEST_F(EccentricityLayersTest, LayersAtOnePitchRegisterExactly) {
    render::EccentricityLayerSettings s = settings();
    s.slope = 1e-4;            // every s_i = 1
    s.radiiDeg = {10.0, 25.0}; // layers wide enough to matter (the optimum would shrink them)
    s.jitter = false;
    s.temporal = false;
    render::EccentricityLayers three(renderer().methodContext(), s);
    s.radiiDeg.clear();
    s.layers = 1;
    render::EccentricityLayers one(renderer().methodContext(), s);
    render::View a = view(three, "three");
    render::View b = view(one, "one");
    a.gaze = b.gaze = {70.0f, 50.0f};
    ASSERT_EQ(three.layout(a).grids.size(), 3u);
    EXPECT_FLOAT_EQ(three.layout(a).grids[1].pitch, 1.0f);
    EXPECT_GT(three.layout(a).grids[0].radiusPx, 15.0f);
    EXPECT_GT(three.layout(a).grids[1].radiusPx, 40.0f);
    EXPECT_EQ(frame(a), frame(b));
}

// No seams at the layer borders of a converged still view: in a band 8 px wide along each inner
// layer's edge, the mean absolute difference to the reference is at most 1.5x the same measure
// just inside and outside the band. The view looks at the stalls along the right side, so the
// band and its surroundings hold similar detail.
TEST_F(EccentricityLayersTest, ConvergedLayersShowNoSeams) {
    render::FullResolution reference(renderer().methodContext(), {32, 7});
    render::View refView = view(reference, "reference");
    refView.camera = sideCamera();
    const std::vector<uint8_t> ref = frame(refView);
    render::EccentricityLayers layers(renderer().methodContext(), settings());
    render::View v = view(layers, "seams");
    v.camera = sideCamera();
    std::vector<uint8_t> last;
    for (int i = 0; i < 24; ++i) {
        last = frame(v);
    }
    auto mad = [&](auto&& keep) {
        double sum = 0.0;
        uint64_t n = 0;
        for (uint32_t y = 0; y < kH; ++y) {
            for (uint32_t x = 0; x < kW; ++x) {
                if (!keep(glm::length(glm::vec2(static_cast<float>(x), static_cast<float>(y)) -
                                      v.gaze))) {
                    continue;
                }
                for (int c = 0; c < 3; ++c) {
                    const std::size_t i = (static_cast<std::size_t>(y) * kW + x) * 4 + c;
                    sum += std::abs(static_cast<int>(last[i]) - static_cast<int>(ref[i]));
                }
                n += 3;
            }
        }
        return n ? sum / static_cast<double>(n) : 0.0;
    };
    const render::LayerLayout& lay = layers.layout(v);
    for (std::size_t l = 0; l + 1 < lay.grids.size(); ++l) {
        const float r = lay.grids[l].radiusPx;
        const double band = mad([&](float d) { return std::abs(d - r) <= 4.0f; });
        const double around =
            mad([&](float d) { return std::abs(d - r) > 4.0f && std::abs(d - r) <= 20.0f; });
        EXPECT_LE(band, 1.5 * around) << "layer " << l + 1 << " border at " << r << " px";
        std::printf("layer %zu border at %.1f px: band %.2f/255, around it %.2f/255\n", l + 1, r,
                    band, around);
    }
}

} // namespace
} // namespace gt

namespace gt {
namespace {

// Geometric LOD by eccentricity on builtin:gallery (subdivision cages): the inner layers trace
// full detail whether LOD is on or off, the outer layer (pitch >= 4 px) a coarser refinement.
TEST(LayersLod, OuterLayerTracesCoarserGeometry) {
    render::Renderer renderer({.scene = "builtin:gallery", .validate = true});
    const uint32_t errorsBefore = renderer.context().validationErrors();
    ASSERT_EQ(renderer.lodTriangles().size(), 3u);
    EXPECT_LT(renderer.lodTriangles()[1], renderer.lodTriangles()[0]);
    render::EccentricityLayerSettings s;
    s.slope = 0.25;
    s.jitter = false;
    s.temporal = false;
    render::EccentricityLayers withLod(renderer.methodContext(), s);
    s.lod = false;
    render::EccentricityLayers without(renderer.methodContext(), s);
    auto render = [&](render::EccentricityLayers& m, const std::string& name) {
        render::View v;
        v.name = name;
        v.camera = renderer.scene().camera;
        v.width = 320;
        v.height = 180;
        v.gaze = {160.0f, 90.0f};
        v.method = &m;
        render::ReadbackTarget readback(renderer.context());
        render::OutputTarget* const target = &readback;
        (void)renderer.renderFrame(std::span(&v, 1), std::span(&target, 1));
        return std::pair{readback.takePixels(), m.layout(v)};
    };
    const auto [on, layout] = render(withLod, "on");
    const auto [off, layoutOff] = render(without, "off");
    ASSERT_EQ(layout.grids.size(), 3u);
    ASSERT_GE(layout.grids[2].pitch, 4.0f);
    ASSERT_LT(layout.grids[1].pitch, 4.0f);
    // Inside 0.6 of the middle layer's radius only full-detail layers show: identical there.
    const float inner = 0.6f * layout.grids[1].radiusPx;
    uint64_t outerDiffer = 0;
    for (uint32_t y = 0; y < 180; ++y) {
        for (uint32_t x = 0; x < 320; ++x) {
            const std::size_t i = (static_cast<std::size_t>(y) * 320 + x) * 4;
            const bool same = on[i] == off[i] && on[i + 1] == off[i + 1] && on[i + 2] == off[i + 2];
            if (glm::length(glm::vec2(static_cast<float>(x), static_cast<float>(y)) -
                            glm::vec2(160.0f, 90.0f)) < inner) {
                ASSERT_TRUE(same) << x << "," << y;
            } else if (!same) {
                ++outerDiffer;
            }
        }
    }
    EXPECT_GT(outerDiffer, 0u) << "the outer layer traced the same geometry with LOD on";
    EXPECT_EQ(renderer.context().validationErrors(), errorsBefore);
}

} // namespace
} // namespace gt
