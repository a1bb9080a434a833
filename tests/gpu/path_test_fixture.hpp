#pragma once
// The path-tracing tests' fixture: the reference pass's linear radiance for a scene, with the
// integrator and bounces given and the firefly clamp off.
#include <memory>
#include <vector>

#include "readback/readback.hpp"
#include "reference/reference.hpp"
#include "render_graph/render_graph.hpp"
#include "support/gpu_test_context.hpp"
#include "trace/gpu_scene.hpp"
#include "vk/resources.hpp"

namespace gt::test {

class PathFixture : public GpuTest {
protected:
    // Linear radiance (rgb) and first-hit distance (a) of the reference pass with `integrator`
    // and `bounces`, firefly clamp off.
    std::vector<glm::vec4> render(const trace::GpuScene& gpuScene, const scene::Scene& s,
                                  uint32_t size, uint32_t spp, uint32_t seed,
                                  trace::Integrator integrator, uint32_t bounces,
                                  trace::SampleSequence sequence = trace::SampleSequence::Sobol) {
        vk::Buffer host(ctx(), {static_cast<VkDeviceSize>(size) * size * 16,
                                VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUsage::Readback,
                                "test.readback"});
        rg::RenderGraph graph(size, size);
        const rg::BufferId hostId = graph.importBuffer(
            "host", {host.handle(), host.size(), std::nullopt, rg::Access::HostRead});
        const passes::ReferenceSettings settings{spp, seed, {integrator, bounces, 0.0f, sequence}};
        const rg::TextureId radiance =
            mReference->add(graph, gpuScene, trace::cameraPush(s.camera, 1.0f), settings);
        passes::addReadbackPass(graph, "radiance", radiance, hostId);
        rg::TransientPool pool(ctx());
        graph.executeAndWait(graph.compile(), pool);
        std::vector<glm::vec4> out(static_cast<std::size_t>(size) * size);
        host.download(std::as_writable_bytes(std::span(out)));
        return out;
    }

    void SetUp() override {
        test::GpuTest::SetUp();
        mReference = std::make_unique<passes::ReferencePass>(ctx());
    }
    void TearDown() override {
        mReference.reset();
        test::GpuTest::TearDown();
    }

    std::unique_ptr<passes::ReferencePass> mReference;
};

} // namespace gt::test
