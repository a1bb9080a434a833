// Pass `lens` on a device: a grid whose pixels encode their own coordinates goes through the
// pass, and at check points the panel shows the coordinates the lens model predicts.
#include <cmath>

#include <gtest/gtest.h>

#include "display/hmd_profile.hpp"
#include "lens/lens.hpp"
#include "readback/readback.hpp"
#include "render_graph/render_graph.hpp"
#include "support/gpu_test_context.hpp"
#include "support/graph_fill.hpp"
#include "vk/resources.hpp"

namespace gt {
namespace {

class LensTest : public test::GpuTest {};

TEST_F(LensTest, MapsAKnownGridWhereTheModelSays) {
    constexpr uint32_t w = 128, h = 144;
    // The grid: R = x / (w - 1), G = y / (h - 1) (sRGB-encoded bytes, as the tone mapper
    // writes), uploaded into a storage image through a copy.
    std::vector<uint8_t> grid(w * h * 4);
    for (uint32_t y = 0; y < h; ++y) {
        for (uint32_t x = 0; x < w; ++x) {
            uint8_t* p = &grid[(y * w + x) * 4];
            p[0] = static_cast<uint8_t>(std::lround(255.0 * x / (w - 1)));
            p[1] = static_cast<uint8_t>(std::lround(255.0 * y / (h - 1)));
            p[2] = 0;
            p[3] = 255;
        }
    }
    vk::Buffer upload(ctx(), {grid.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                              vk::MemoryUsage::Upload, "grid.upload"});
    upload.upload(std::as_bytes(std::span(grid)));
    vk::Buffer host(ctx(), {grid.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                            vk::MemoryUsage::Readback, "panel.host"});
    display::LensModel lens = display::hmdProfile(display::HmdModel::Fove).lens;
    lens.chroma = glm::vec3(1.0f); // one sample position for every channel
    const glm::vec2 centre(0.55f, 0.5f);
    rg::RenderGraph g(w, h);
    const rg::BufferId src =
        g.importBuffer("grid", {upload.handle(), upload.size(), std::nullopt, std::nullopt});
    const rg::BufferId dst =
        g.importBuffer("panel", {host.handle(), host.size(), std::nullopt, rg::Access::HostRead});
    const rg::TextureId gridImage =
        test::addUploadedTexture(g, "grid.image", src, VK_FORMAT_R8G8B8A8_UNORM);
    const passes::LensPass pass(ctx());
    passes::addReadbackPass(g, "panel", pass.add(g, gridImage, lens, centre), dst);
    rg::TransientPool pool(ctx());
    (void)g.executeAndWait(g.compile(), pool);
    std::vector<uint8_t> panel(grid.size());
    host.download(std::as_writable_bytes(std::span(panel)));

    const float aspect = static_cast<float>(w) / static_cast<float>(h);
    int checked = 0;
    for (const glm::uvec2 p : {glm::uvec2(70, 72), glm::uvec2(20, 20), glm::uvec2(110, 130),
                               glm::uvec2(10, 100), glm::uvec2(120, 10), glm::uvec2(64, 140)}) {
        const glm::vec2 q = (glm::vec2(p) + 0.5f) / glm::vec2(w, h);
        const glm::vec2 s = lens.sourceOf(q, centre, aspect, 1);
        // The grid value at s (pixel centres at (i + 0.5) / size).
        const glm::vec2 expected = (s * glm::vec2(w, h) - 0.5f) / glm::vec2(w - 1, h - 1);
        const uint8_t* got = &panel[(p.y * w + p.x) * 4];
        EXPECT_NEAR(got[0] / 255.0f, expected.x, 2.5f / 255.0f) << p.x << "," << p.y;
        EXPECT_NEAR(got[1] / 255.0f, expected.y, 2.5f / 255.0f) << p.x << "," << p.y;
        // And it moved: barrel distortion pulls every check point towards the centre.
        const glm::vec2 undistorted = (q * glm::vec2(w, h) - 0.5f) / glm::vec2(w - 1, h - 1);
        if (glm::length(q - centre) > 0.2f) {
            EXPECT_GT(glm::length(expected - undistorted), 6.0f / 255.0f);
        }
        ++checked;
    }
    EXPECT_EQ(checked, 6);
}

} // namespace
} // namespace gt
