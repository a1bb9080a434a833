// Pass `edge_rays` (passes/edge_rays): on a reconstructed image whose motion is built here, a
// pixel gets a ray of its own exactly where its 3x3 neighbourhood shows more than one surface and
// one of them moves; every other pixel, a still edge's included, is copied unchanged, motion too.
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "edge_rays/edge_rays.hpp"
#include "render_graph/render_graph.hpp"
#include "scene/builtin_scenes.hpp"
#include "scene/bvh.hpp"
#include "support/gpu_test_context.hpp"
#include "support/graph_fill.hpp"
#include "trace/gpu_scene.hpp"
#include "vk/resources.hpp"

namespace gt {
namespace {

constexpr uint32_t kW = 64, kH = 48;
const glm::vec4 kMagenta{1.0f, 0.0f, 1.0f, 7.0f}; // the reconstruction: no scene shows this

// Motion texels: surface 1 standing still, a block of surface 2 moving (x 20-39, y 12-35) and a
// block of surface 3 standing still (x 48-59, y 12-35); signature codes as motion.glsl's.
glm::vec4 motionAt(uint32_t x, uint32_t y) {
    const bool rows = y >= 12 && y < 36;
    if (rows && x >= 20 && x < 40) return {0.1f, 0.0f, 0.0f, static_cast<float>((2u << 8u) | 1u)};
    if (rows && x >= 48 && x < 60) return {0.0f, 0.0f, 0.0f, static_cast<float>((3u << 8u) | 1u)};
    return {0.0f, 0.0f, 0.0f, static_cast<float>((1u << 8u) | 1u)};
}

// Whether the 3x3 pixels around (x, y) show more than one surface, one of them moving.
bool onMovingEdge(uint32_t x, uint32_t y) {
    bool mixed = false, moving = false;
    const float first = motionAt(x, y).w;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            const int xx = std::clamp(static_cast<int>(x) + dx, 0, static_cast<int>(kW) - 1);
            const int yy = std::clamp(static_cast<int>(y) + dy, 0, static_cast<int>(kH) - 1);
            const glm::vec4 m = motionAt(static_cast<uint32_t>(xx), static_cast<uint32_t>(yy));
            mixed = mixed || m.w != first;
            moving = moving || m.x != 0.0f;
        }
    }
    return mixed && moving;
}

class EdgeRaysTest : public test::GpuTest {
protected:
    // The pass over the image above (with a support image when `support`); the radiance or,
    // with `readMotion`, the motion it writes.
    std::vector<glm::vec4> run(bool support, bool readMotion) {
        rg::RenderGraph g(kW, kH);
        std::vector<glm::vec4> motion(static_cast<std::size_t>(kW) * kH);
        for (uint32_t y = 0; y < kH; ++y) {
            for (uint32_t x = 0; x < kW; ++x)
                motion[y * kW + x] = motionAt(x, y);
        }
        const std::span<const std::byte> bytes = std::as_bytes(std::span(motion));
        vk::Buffer upload(ctx(), {bytes.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                  vk::MemoryUsage::Upload, "motion"});
        upload.upload(bytes);
        const rg::BufferId src = g.importBuffer(
            "motion.upload", {upload.handle(), upload.size(), std::nullopt, std::nullopt});
        passes::EdgeRaysImage in{
            test::addFilledTexture(g, "radiance", {VK_FORMAT_R32G32B32A32_SFLOAT}, kMagenta),
            test::addUploadedTexture(g, "motion", src, VK_FORMAT_R32G32B32A32_SFLOAT),
            std::nullopt};
        if (support) {
            in.support =
                test::addFilledTexture(g, "support", {VK_FORMAT_R32_SFLOAT}, glm::vec4(0.7f));
        }
        const passes::EdgeRaysImage out = mPass.add(
            g, mGpu, trace::cameraPush(mScene.camera, static_cast<float>(kW) / kH), in, 3u);
        return test::executeAndRead(ctx(), g, readMotion ? out.motion : out.radiance, nullptr);
    }

    scene::Scene mScene = scene::makeCornell();
    scene::Bvh mBvh{mScene};
    trace::GpuScene mGpu{ctx(), mScene, mBvh};
    passes::EdgeRaysPass mPass{ctx()};
};

TEST_F(EdgeRaysTest, TracesExactlyThePixelsOnAMovingEdge) {
    for (const bool support : {false, true}) {
        const std::vector<glm::vec4> radiance = run(support, false);
        const std::vector<glm::vec4> motion = run(support, true);
        std::size_t traced = 0, wrong = 0;
        for (uint32_t y = 0; y < kH; ++y) {
            for (uint32_t x = 0; x < kW; ++x) {
                const glm::vec4 c = radiance[y * kW + x];
                const bool copied = c == kMagenta && motion[y * kW + x] == motionAt(x, y);
                // The Cornell box seen from its camera: a hit, at a finite distance.
                const bool rayTraced = c != kMagenta && std::isfinite(c.a) && c.a > 0.0f;
                if (onMovingEdge(x, y)) {
                    traced += rayTraced ? 1 : 0;
                    wrong += rayTraced ? 0 : 1;
                } else {
                    wrong += copied ? 0 : 1;
                }
            }
        }
        // The moving block's rings inside and outside its border: 84 + 92 pixels.
        EXPECT_EQ(traced, 84u + 92u) << "support " << support;
        EXPECT_EQ(wrong, 0u) << "support " << support;
    }
}

} // namespace
} // namespace gt
