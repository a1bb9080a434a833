// TAA: on a static scene with per-frame jitter the output converges (frame-to-frame change
// falls); a gaze jump drops the history so the output is the current frame at once.
#include <cmath>
#include <optional>

#include "readback/readback.hpp"
#include "reference/reference.hpp"
#include "render_graph/render_graph.hpp"
#include "scene/builtin_scenes.hpp"
#include "scene/bvh.hpp"
#include "support/gpu_test_context.hpp"
#include "support/graph_fill.hpp"
#include "taa/taa.hpp"
#include "trace/gpu_scene.hpp"
#include "vk/resources.hpp"

namespace gt {
namespace {

class TaaTest : public test::GpuTest {
protected:
    static constexpr uint32_t kW = 64, kH = 64;
    struct Frame {
        std::vector<glm::vec4> current, output;
    };

    // The previous frame's gaze (the history's camera never moves here).
    std::optional<glm::vec2> lastGaze;

    Frame frame(const trace::GpuScene& gs, const scene::Scene& s, rg::HistoryPool& history,
                uint32_t seed, glm::vec2 gaze) {
        vk::Buffer cur(ctx(), {kW * kH * 16, 0, vk::MemoryUsage::Readback, "cur"});
        vk::Buffer out(ctx(), {kW * kH * 16, 0, vk::MemoryUsage::Readback, "out"});
        rg::RenderGraph g(kW, kH);
        const auto curId =
            g.importBuffer("cur", {cur.handle(), cur.size(), std::nullopt, rg::Access::HostRead});
        const auto outId =
            g.importBuffer("out", {out.handle(), out.size(), std::nullopt, rg::Access::HostRead});
        const passes::ReferencePass reference(ctx());
        const passes::TaaPass taa(ctx());
        const auto camera = trace::cameraPush(s.camera, 1.0f);
        const rg::TextureId radiance = reference.add(g, gs, camera, {1, seed});
        const rg::HistoryTextures h =
            g.importHistory(history, "taa", VK_FORMAT_R32G32B32A32_SFLOAT, kW, kH);
        const bool reset = passes::taaMustReset(h.valid && lastGaze.has_value(), false, gaze,
                                                lastGaze.value_or(gaze), kW, {});
        const rg::TextureId resolved = taa.add(g, h, radiance, camera, camera, reset);
        passes::addReadbackPass(g, "cur", radiance, curId);
        passes::addReadbackPass(g, "out", resolved, outId);
        rg::TransientPool pool(ctx());
        g.executeAndWait(g.compile(), pool);
        history.commit(g);
        lastGaze = gaze;
        Frame f{std::vector<glm::vec4>(kW * kH), std::vector<glm::vec4>(kW * kH)};
        cur.download(std::as_writable_bytes(std::span(f.current)));
        out.download(std::as_writable_bytes(std::span(f.output)));
        return f;
    }

    static double meanDiff(const std::vector<glm::vec4>& a, const std::vector<glm::vec4>& b) {
        double d = 0.0;
        for (std::size_t i = 0; i < a.size(); ++i)
            d += glm::length(glm::vec3(a[i] - b[i]));
        return d / static_cast<double>(a.size());
    }
};

TEST_F(TaaTest, ConvergesOnStaticSceneAndResetsOnGazeJump) {
    const scene::Scene s = scene::makeCornell();
    const scene::Bvh bvh(s);
    const trace::GpuScene gs(ctx(), s, bvh);
    rg::HistoryPool history(ctx());
    const glm::vec2 gaze(32.0f, 32.0f);
    std::vector<Frame> frames;
    for (uint32_t i = 0; i < 12; ++i)
        frames.push_back(frame(gs, s, history, i + 1, gaze));
    // First frame: no history, output == current.
    EXPECT_EQ(meanDiff(frames[0].output, frames[0].current), 0.0);
    // The raw frames keep changing (jitter); the resolved ones settle.
    const double rawChange = meanDiff(frames[10].current, frames[11].current);
    const double earlyChange = meanDiff(frames[0].output, frames[1].output);
    const double lateChange = meanDiff(frames[10].output, frames[11].output);
    EXPECT_GT(rawChange, 0.0);
    EXPECT_LT(lateChange, 0.5 * rawChange);
    EXPECT_LT(lateChange, earlyChange);
    EXPECT_EQ(history.frames("taa"), 12u);
    // A gaze jump of more than 1/16 of the width: history dropped, output == current.
    const Frame jumped = frame(gs, s, history, 99, glm::vec2(60.0f, 10.0f));
    EXPECT_EQ(meanDiff(jumped.output, jumped.current), 0.0);
    // A small gaze move keeps the history (fixation jitter is not a saccade).
    const Frame small = frame(gs, s, history, 100, glm::vec2(61.0f, 10.0f));
    EXPECT_GT(meanDiff(small.output, small.current), 0.0);
}

// A still view with the support of a sparse method (taa.glsl): each frame counts by
// w = 0.002 + exp(-(s / 0.2)^2) of how near its samples fell, in a running mean whose weight
// sum is a history of its own. A frame whose samples fell far away barely moves the pixel;
// the plain running mean would take it at 1 / (n + 1).
TEST_F(TaaTest, SupportWeighsAStillViewsFrames) {
    rg::HistoryPool history(ctx());
    shaders::trace::CameraPush camera{};
    camera.origin = glm::vec4(0.0f, 0.0f, 0.0f, 0.5f);
    camera.forward = glm::vec4(0.0f, 0.0f, -1.0f, 1.0f);
    camera.right = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
    camera.up = glm::vec4(0.0f, 1.0f, 0.0f, 0.0f);
    auto run = [&](float grey, float support, uint32_t samples, bool withSupport) {
        rg::RenderGraph g(kW, kH);
        auto fill = [&](const char* name, VkFormat format, glm::vec4 c) {
            return test::addFilledTexture(g, name, {format}, c);
        };
        const rg::TextureId current =
            fill("current", VK_FORMAT_R32G32B32A32_SFLOAT, glm::vec4(glm::vec3(grey), 5.0f));
        std::optional<passes::TaaSupport> sup;
        if (withSupport) {
            sup = passes::TaaSupport{
                fill("support", VK_FORMAT_R32_SFLOAT, glm::vec4(support)),
                g.importHistory(history, "taa.weight", VK_FORMAT_R32_SFLOAT, kW, kH)};
        }
        const rg::HistoryTextures h =
            g.importHistory(history, "taa", VK_FORMAT_R32G32B32A32_SFLOAT, kW, kH);
        const passes::TaaFrameState state{0.0f, glm::vec2(32.0f), true, true, samples};
        const passes::TaaPass taa(ctx());
        const rg::TextureId out =
            taa.add(g, h, current, camera, camera, samples == 0, {}, state, sup);
        const std::vector<glm::vec4> px = test::executeAndRead(ctx(), g, out, &history);
        return px[static_cast<std::size_t>(kW) * 20 + 20].r;
    };
    const float w0 = 0.002f + 1.0f, w1 = 0.002f + std::exp(-25.0f);
    EXPECT_FLOAT_EQ(run(0.2f, 0.0f, 0, true), 0.2f); // a reset: the frame itself
    const float second = run(0.8f, 1.0f, 1, true);   // its samples fell a spacing away
    EXPECT_NEAR(second, 0.2f + 0.6f * w1 / (w0 + w1), 1e-5f);
    const float third = run(0.6f, 0.0f, 2, true); // on the pixel again
    EXPECT_NEAR(third, second + (0.6f - second) * w0 / (w0 + w1 + w0), 1e-5f);
    // Without a support: the plain running mean, 1 / (n + 1).
    (void)run(0.2f, 0.0f, 0, false);
    EXPECT_NEAR(run(0.8f, 1.0f, 1, false), 0.5f, 1e-5f);
}

} // namespace
} // namespace gt
