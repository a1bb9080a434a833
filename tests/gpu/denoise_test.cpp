// Pass `denoise`: it smooths noise away from the gaze and leaves the fovea as it was, evenly
// over the image (every row alike), and it does not blend across a depth edge.
#include <cmath>
#include <random>
#include <vector>

#include "denoise/denoise.hpp"
#include "render_graph/render_graph.hpp"
#include "scene/scene.hpp"
#include "support/gpu_test_context.hpp"
#include "support/graph_fill.hpp"
#include "trace/gpu_scene.hpp"
#include "vk/resources.hpp"

namespace gt {
namespace {

constexpr uint32_t kW = 96, kH = 64;

class DenoiseTest : public test::GpuTest {
protected:
    // The pass over `input` (rgb, a = first-hit distance) with the gaze at `gaze`.
    std::vector<glm::vec4> run(const std::vector<glm::vec4>& input, glm::vec2 gaze,
                               const passes::DenoiseSettings& settings = {}) {
        vk::Buffer upload(ctx(),
                          {input.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                           vk::MemoryUsage::Upload, "denoise.upload"});
        upload.upload(std::as_bytes(std::span(input)));
        rg::RenderGraph g(kW, kH);
        const rg::BufferId src =
            g.importBuffer("input", {upload.handle(), upload.size(), std::nullopt, std::nullopt});
        const rg::TextureId radiance =
            test::addUploadedTexture(g, "radiance", src, VK_FORMAT_R32G32B32A32_SFLOAT);
        scene::Camera camera;
        camera.yfov = glm::radians(60.0f);
        const passes::DenoisePass pass(ctx());
        const rg::TextureId out =
            pass.add(g, radiance, trace::cameraPush(camera, float(kW) / float(kH)), gaze, settings);
        return test::executeAndRead(ctx(), g, out, nullptr);
    }
};

// Grey 0.5 with uniform noise of +-0.3 on a plane at distance 2 (its depth along each ray,
// so the normals from depth all face the camera).
std::vector<glm::vec4> noisyPlane(uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> noise(-0.3f, 0.3f);
    std::vector<glm::vec4> img(static_cast<std::size_t>(kW) * kH);
    const float t = std::tan(glm::radians(30.0f));
    for (uint32_t y = 0; y < kH; ++y) {
        for (uint32_t x = 0; x < kW; ++x) {
            const float sx = (2.0f * (x + 0.5f) / kW - 1.0f) * t * kW / kH;
            const float sy = (1.0f - 2.0f * (y + 0.5f) / kH) * t;
            const float depth = 2.0f * std::sqrt(1.0f + sx * sx + sy * sy);
            img[y * kW + x] = glm::vec4(glm::vec3(0.5f + noise(rng)), depth);
        }
    }
    return img;
}

double rowDeviation(const std::vector<glm::vec4>& img, uint32_t y, uint32_t x0, uint32_t x1) {
    double sum = 0.0, sumSq = 0.0;
    for (uint32_t x = x0; x < x1; ++x) {
        const double v = img[y * kW + x].g;
        sum += v;
        sumSq += v * v;
    }
    const double n = x1 - x0, mean = sum / n;
    return std::sqrt(std::max(sumSq / n - mean * mean, 0.0));
}

// Gaze at the left edge, 60-degree field: the right two thirds are past 15 degrees (full
// strength). There every row's noise falls to under a third; within 5 degrees of the gaze
// nothing changes; the depth (alpha) passes through.
TEST_F(DenoiseTest, SmoothsThePeripheryEvenlyAndLeavesTheFovea) {
    const std::vector<glm::vec4> in = noisyPlane(1);
    const std::vector<glm::vec4> out = run(in, {0.0f, 32.0f});
    double worst = 0.0;
    for (uint32_t y = 0; y < kH; ++y) {
        const double before = rowDeviation(in, y, 40, kW), after = rowDeviation(out, y, 40, kW);
        worst = std::max(worst, after / before);
        EXPECT_LT(after, before / 3.0) << "row " << y;
    }
    std::printf("worst row: noise after / before %.3f\n", worst);
    // 5 degrees is 5 / 60 * 64 = 5.3 pixels from the gaze.
    for (uint32_t y = 30; y < 35; ++y) {
        for (uint32_t x = 0; x < 3; ++x) {
            EXPECT_EQ(out[y * kW + x], in[y * kW + x]) << x << "," << y;
        }
    }
    for (std::size_t i = 0; i < in.size(); ++i)
        ASSERT_EQ(out[i].a, in[i].a);
}

// Two surfaces: dark (0.1) at distance 2 on the left, bright (1.0) at distance 6 on the right,
// noise on both. The dark side next to the edge stays dark.
TEST_F(DenoiseTest, DoesNotBlendAcrossADepthEdge) {
    std::vector<glm::vec4> in = noisyPlane(2);
    for (uint32_t y = 0; y < kH; ++y) {
        for (uint32_t x = 0; x < kW; ++x) {
            glm::vec4& p = in[y * kW + x];
            const bool right = x >= kW / 2;
            p = glm::vec4(glm::vec3((right ? 1.0f : 0.1f) + (p.g - 0.5f) * 0.1f),
                          right ? p.a * 3.0f : p.a);
        }
    }
    const std::vector<glm::vec4> out = run(in, {-500.0f, 32.0f});
    double dark = 0.0;
    for (uint32_t y = 0; y < kH; ++y) {
        for (uint32_t x = kW / 2 - 3; x < kW / 2; ++x)
            dark += out[y * kW + x].g / (3.0 * kH);
    }
    EXPECT_NEAR(dark, 0.1, 0.01);
}

} // namespace
} // namespace gt
