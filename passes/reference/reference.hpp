#pragma once
// Pass `reference`: full-resolution ray tracing with N stratified jittered rays per pixel into a
// linear RGBA32F image — the baseline every foveated method is measured against.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <tuple>

#include "render_graph/render_graph.hpp"
#include "trace/integrator.hpp"
#include "trace_shared.h"

namespace gt::vk {
class Context;
class ComputePipeline;
} // namespace gt::vk
namespace gt::trace {
class GpuScene;
}

namespace gt::passes {

struct ReferenceSettings {
    uint32_t raysPerPixel = 1;
    uint32_t frameSeed = 0;
    trace::IntegratorSettings integrator{};
};

// The radiance (rgb; a = the first ray's first-hit distance) and, in a scene that moves
// (trace::GpuScene::dynamic()), that hit's motion (shaders/common/motion.glsl).
struct ReferenceImage {
    rg::TextureId radiance;
    std::optional<rg::TextureId> motion;
};

class ReferencePass {
public:
    explicit ReferencePass(vk::Context& ctx);
    ~ReferencePass();
    // Adds "reference.trace" writing a new output-sized texture "reference.radiance", seen
    // through `camera` (trace::cameraPush).
    rg::TextureId add(rg::RenderGraph& graph, const trace::GpuScene& scene,
                      const shaders::trace::CameraPush& camera,
                      const ReferenceSettings& settings) const;
    // The same, and in a scene that moves a new texture "reference.motion" too.
    ReferenceImage addImage(rg::RenderGraph& graph, const trace::GpuScene& scene,
                            const shaders::trace::CameraPush& camera,
                            const ReferenceSettings& settings) const;

private:
    // Built on first use: without and with the alpha test (trace.glsl's kAlphaMask), for a
    // static or moving scene, per integrator.
    const vk::ComputePipeline& pipeline(bool alphaMask, bool dynamic,
                                        const trace::IntegratorSettings& integrator = {}) const;

    vk::Context& mCtx;
    mutable std::map<std::tuple<bool, bool, uint32_t, uint32_t, float, uint32_t>,
                     std::unique_ptr<vk::ComputePipeline>>
        mPipelines;
};

} // namespace gt::passes
