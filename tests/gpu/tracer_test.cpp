// The compute tracer against the CPU reference implementation of the same shading, and the
// structure of the built-in market scene.
#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "readback/readback.hpp"
#include "reference/reference.hpp"
#include "render_graph/render_graph.hpp"
#include "scene/builtin_scenes.hpp"
#include "scene/bvh.hpp"
#include "scene/environment.hpp"
#include "scene/gltf_loader.hpp"
#include "support/gpu_test_context.hpp"
#include "tonemap/tonemap.hpp"
#include "trace/cpu_tracer.hpp"
#include "trace/gpu_scene.hpp"
#include "vk/resources.hpp"

namespace gt {
namespace {

class TracerTest : public test::GpuTest {
protected:
    // Linear radiance from the GPU reference pass.
    std::vector<glm::vec4> renderGpu(const scene::Scene& s, const scene::Bvh& bvh, uint32_t w,
                                     uint32_t h, uint32_t spp) {
        const trace::GpuScene gpuScene(ctx(), s, bvh);
        const passes::ReferencePass reference(ctx());
        vk::Buffer host(ctx(),
                        {static_cast<VkDeviceSize>(w) * h * 16, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                         vk::MemoryUsage::Readback, "test.readback"});
        rg::RenderGraph graph(w, h);
        const rg::BufferId hostId = graph.importBuffer(
            "host", {host.handle(), host.size(), std::nullopt, rg::Access::HostRead});
        const rg::TextureId radiance = reference.add(
            graph, gpuScene,
            trace::cameraPush(s.camera, static_cast<float>(w) / static_cast<float>(h)), {spp, 7});
        passes::addReadbackPass(graph, "radiance", radiance, hostId);
        rg::TransientPool pool(ctx());
        graph.executeAndWait(graph.compile(), pool);
        std::vector<glm::vec4> out(static_cast<std::size_t>(w) * h);
        host.download(std::as_writable_bytes(std::span(out)));
        return out;
    }

    // Mean absolute difference relative to the mean CPU radiance, and the share of pixels that
    // differ by more than 1 % of the mean (edge pixels may flip between triangles on ULPs).
    void compare(const scene::Scene& s, uint32_t w, uint32_t h, uint32_t spp) {
        const scene::Bvh bvh(s);
        const std::vector<glm::vec4> gpu = renderGpu(s, bvh, w, h, spp);
        const trace::CpuTracer cpu(s, bvh);
        const std::vector<glm::vec4> ref = cpu.render({w, h, spp, 7});
        double diff = 0.0, mean = 0.0;
        std::size_t outliers = 0;
        for (std::size_t i = 0; i < ref.size(); ++i) {
            ASSERT_TRUE(std::isfinite(gpu[i].x + gpu[i].y + gpu[i].z)) << "pixel " << i;
            const double d = std::abs(gpu[i].x - ref[i].x) + std::abs(gpu[i].y - ref[i].y) +
                             std::abs(gpu[i].z - ref[i].z);
            diff += d / 3.0;
            mean += (ref[i].x + ref[i].y + ref[i].z) / 3.0;
        }
        mean /= static_cast<double>(ref.size());
        diff /= static_cast<double>(ref.size());
        for (std::size_t i = 0; i < ref.size(); ++i) {
            const double d = (std::abs(gpu[i].x - ref[i].x) + std::abs(gpu[i].y - ref[i].y) +
                              std::abs(gpu[i].z - ref[i].z)) /
                             3.0;
            if (d > 0.01 * mean) ++outliers;
        }
        // Tolerance: 0.5 % of the mean radiance on average, at most 1 % of pixels off.
        EXPECT_LT(diff / mean, 0.005) << s.name << " mean " << mean << " diff " << diff;
        EXPECT_LT(static_cast<double>(outliers) / static_cast<double>(ref.size()), 0.01)
            << s.name << ": " << outliers << " pixels differ by more than 1 %";
    }
};

TEST_F(TracerTest, GpuMatchesCpuOnCornell) {
    compare(scene::makeCornell(), 64, 64, 2);
}

TEST_F(TracerTest, GpuMatchesCpuOnMarket) {
    compare(scene::makeMarket(), 96, 64, 1);
}

TEST_F(TracerTest, GpuMatchesCpuOnTexturedGltf) {
    const auto content = test::sharedContent();
    if (content.empty()) GTEST_SKIP() << "../shared/content is absent";
    const auto file = content / "khronos_AnimatedCube" / "AnimatedCube.gltf";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " is absent";
    compare(scene::loadGltf(file), 64, 64, 1);
}

TEST_F(TracerTest, UnlitMaterialsShowTheirBaseColour) {
    // KHR_materials_unlit: every surface of the box shows its base colour, whatever the lights.
    scene::Scene s = scene::makeCornell();
    const glm::vec4 colour(0.2f, 0.4f, 0.6f, 1.0f);
    for (scene::Material& m : s.materials) {
        m.unlit = true;
        m.baseColor = colour;
        m.baseColorTexture = -1;
    }
    compare(s, 48, 48, 1);
    const scene::Bvh bvh(s);
    const std::vector<glm::vec4> gpu = renderGpu(s, bvh, 48, 48, 1);
    const auto flat = std::count_if(gpu.begin(), gpu.end(), [&](const glm::vec4& p) {
        return glm::all(
            glm::lessThan(glm::abs(glm::vec3(p) - glm::vec3(colour)), glm::vec3(1e-5f)));
    });
    EXPECT_GT(flat, static_cast<long>(gpu.size() / 2)) << "pixels showing the unlit colour";
}

TEST_F(TracerTest, AlphaMaskPassesRaysThroughCutOutTexels) {
    // A screen of 8x8 checker cells, alternately opaque red and fully transparent, between the
    // camera and the box, and in the way of its light: camera and shadow rays pass the holes.
    auto withScreen = [](float cutoff) {
        scene::Scene s = scene::makeCornell();
        scene::Texture t;
        t.width = t.height = 8;
        for (uint32_t y = 0; y < 8; ++y) {
            for (uint32_t x = 0; x < 8; ++x) {
                t.rgba.push_back((x + y) % 2 == 0 ? 0xFF0000FFu : 0x00FFFFFFu);
            }
        }
        s.textures.push_back(t);
        scene::Material m;
        m.baseColorTexture = static_cast<int>(s.textures.size()) - 1;
        m.alphaCutoff = cutoff;
        scene::SceneBuilder b(s);
        const uint32_t id = b.material(m);
        b.quad({-1.2f, -0.2f, 2.0f}, {2.4f, 0.0f, 0.0f}, {0.0f, 2.4f, 0.0f}, id);
        b.quad({-0.8f, 1.6f, -0.8f}, {1.6f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.6f}, id);
        return s;
    };
    const scene::Scene masked = withScreen(0.5f);
    compare(masked, 48, 48, 2);
    // Half the screen's texels are holes: the masked picture shows much more of the box.
    const scene::Bvh maskedBvh(masked);
    const scene::Scene opaque = withScreen(-1.0f);
    const scene::Bvh opaqueBvh(opaque);
    const std::vector<glm::vec4> a = renderGpu(masked, maskedBvh, 48, 48, 1);
    const std::vector<glm::vec4> b = renderGpu(opaque, opaqueBvh, 48, 48, 1);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        differ += glm::length(glm::vec3(a[i]) - glm::vec3(b[i])) > 0.05f ? 1 : 0;
    }
    EXPECT_GT(differ, a.size() / 5) << "pixels changed by the holes";
}

TEST_F(TracerTest, GpuMatchesCpuOnEnvironment) {
    // cubemap: scenes sample the environment on every miss; a procedural 64x32 panorama with
    // sharp features in all directions, and the Cornell box inside it.
    scene::Environment env;
    env.width = 64;
    env.height = 32;
    for (uint32_t y = 0; y < 32; ++y) {
        for (uint32_t x = 0; x < 64; ++x) {
            // Smooth in every direction, so that lavapipe's atan/acos approximations move the
            // lookups by far less than the tolerance; distinct per direction, so a wrong mapping
            // or orientation fails.
            const float u = static_cast<float>(x) / 64.0f, v = static_cast<float>(y) / 32.0f;
            env.texels.emplace_back(0.5f + 0.5f * std::sin(6.2831853f * u), v * v,
                                    1.0f + 0.5f * std::cos(6.2831853f * u + 3.0f * v), 1.0f);
        }
    }
    scene::Scene empty;
    empty.name = "cubemap:test";
    empty.environment = env;
    empty.camera.position = glm::vec3(0.0f);
    empty.camera.forward = glm::normalize(glm::vec3(0.3f, 0.2f, -1.0f));
    empty.camera.yfov = 1.5f;
    compare(empty, 64, 48, 1);
    scene::Scene box = scene::makeCornell();
    box.environment = env;
    box.camera.position = {0.0f, 1.0f, 6.0f};
    compare(box, 64, 48, 1);
}

TEST(Environment, RejectsWrongAspectAndMissingFiles) {
    const auto dir = test::tempDir("env");
    EXPECT_THROW((void)scene::loadEnvironment(dir / "none.hdr"), LoadError);
    EXPECT_THROW((void)scene::loadEnvironment(dir), LoadError); // a folder without faces
    const auto content = test::sharedContent();
    if (content.empty()) GTEST_SKIP() << "../shared/content is absent";
    const scene::Environment eq = scene::loadEnvironment(content / "env_spiaggia_di_mondello_1k" /
                                                         "spiaggia_di_mondello_1k.hdr");
    EXPECT_EQ(eq.width, 2 * eq.height);
    const scene::Environment cube = scene::loadEnvironment(content / "env_venice_cubemap");
    EXPECT_EQ(cube.width, 2 * cube.height);
    // The Venice sunset sky is brighter straight up than the ground straight down.
    auto lum = [](glm::vec3 c) { return c.r + c.g + c.b; };
    EXPECT_GT(lum(scene::sampleEnvironment(eq, {0, 0.3f, -1})), 0.0f);
    EXPECT_GT(lum(scene::sampleEnvironment(cube, {0, 1, 0})),
              lum(scene::sampleEnvironment(cube, {0, -1, 0})));
}

TEST_F(TracerTest, MarketHasDarkAndBrightRegions) {
    // The market exists to be high-contrast (thesis, 6.3): both near-black pillars and
    // near-white walls and lights must be on screen, and the image must not be flat.
    const scene::Scene s = scene::makeMarket();
    const scene::Bvh bvh(s);
    const trace::GpuScene gpuScene(ctx(), s, bvh);
    const passes::ReferencePass reference(ctx());
    const passes::TonemapPass tonemap(ctx());
    constexpr uint32_t w = 160, h = 180;
    vk::Buffer host(ctx(), {w * h * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUsage::Readback,
                            "test.ldr"});
    rg::RenderGraph graph(w, h);
    const rg::BufferId hostId = graph.importBuffer(
        "host", {host.handle(), host.size(), std::nullopt, rg::Access::HostRead});
    const auto ldr = tonemap.add(
        graph,
        reference.add(graph, gpuScene,
                      trace::cameraPush(s.camera, static_cast<float>(w) / static_cast<float>(h)),
                      {1, 0}),
        1.0f);
    passes::addReadbackPass(graph, "ldr", ldr, hostId);
    rg::TransientPool pool(ctx());
    graph.executeAndWait(graph.compile(), pool);
    std::vector<uint8_t> px(w * h * 4);
    host.download(std::as_writable_bytes(std::span(px)));
    std::size_t dark = 0, bright = 0;
    double sum = 0.0, sum2 = 0.0;
    for (std::size_t i = 0; i < w * h; ++i) {
        const double l = 0.2126 * px[4 * i] + 0.7152 * px[4 * i + 1] + 0.0722 * px[4 * i + 2];
        dark += l < 40.0;
        bright += l > 215.0;
        sum += l;
        sum2 += l * l;
    }
    const double n = w * h, mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    EXPECT_GT(static_cast<double>(dark) / n, 0.03) << "too few dark pixels (pillars)";
    EXPECT_GT(static_cast<double>(bright) / n, 0.03) << "too few bright pixels (walls, lights)";
    EXPECT_GT(sd, 30.0) << "image is nearly flat";
}

} // namespace
} // namespace gt
