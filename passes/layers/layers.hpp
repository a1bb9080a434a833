#pragma once
// Pass `layers`: eccentricity layers (Guenter et al. 2012). "layers.trace" ray traces one
// layer as a grid over its sub-frustum of the view (run once per layer, each in its own graph
// scope); "layers.compose" resamples every layer bilinearly to the display grid and blends them
// with smoothstep masks around the gaze (Figures 3 and 6). Where the layers go, how they are
// jittered and how their histories are kept is the renderer's EccentricityLayersMethod.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include <glm/glm.hpp>

#include "render_graph/render_graph.hpp"
#include "trace_shared.h"

namespace gt::vk {
class Context;
class ComputePipeline;
} // namespace gt::vk
namespace gt::trace {
class GpuScene;
}

namespace gt::passes {

inline constexpr uint32_t kMaxEccentricityLayers = 4;

// One layer as the compose step sees it.
struct ComposedLayer {
    rg::TextureId image;   // rgb radiance, a = first-hit distance
    glm::vec2 origin{};    // display position of the grid's top-left corner (pixel edges)
    float pitch = 1.0f;    // display pixels per layer pixel (s_i)
    float radiusPx = 0.0f; // where its blend weight reaches 0 (ignored for the outer layer)
};

// One traced layer: rgb radiance, a = first-hit distance; in a scene that moves
// (trace::GpuScene::dynamic()) also that hit's motion (shaders/common/motion.glsl).
struct TracedLayer {
    rg::TextureId radiance;
    std::optional<rg::TextureId> motion;
};

class LayersPass {
public:
    explicit LayersPass(vk::Context& ctx);
    ~LayersPass();
    // Adds "layers.trace" writing a new `width` x `height` texture "layers.radiance" seen through
    // `camera` (the layer's sub-frustum), `raysPerPixel` stratified rays per layer pixel,
    // through the scene's geometric LOD level `lod` (0: full detail).
    rg::TextureId addTrace(rg::RenderGraph& graph, const trace::GpuScene& scene,
                           const shaders::trace::CameraPush& camera, uint32_t width,
                           uint32_t height, uint32_t raysPerPixel, uint32_t lod = 0) const;
    // The same, and in a scene that moves a new texture "layers.motion" of the layer's size.
    TracedLayer addTraceImage(rg::RenderGraph& graph, const trace::GpuScene& scene,
                              const shaders::trace::CameraPush& camera, uint32_t width,
                              uint32_t height, uint32_t raysPerPixel, uint32_t lod = 0) const;
    // Adds "layers.compose" writing the output-sized "layers.composed": `layers` inner first, the
    // last covering the whole display; `transition` is the smoothstep's share of each radius.
    rg::TextureId addCompose(rg::RenderGraph& graph, std::span<const ComposedLayer> layers,
                             glm::vec2 gaze, float transition) const;

private:
    const vk::ComputePipeline& tracePipeline(bool alphaMask, bool dynamic) const;
    const vk::ComputePipeline& composePipeline(std::size_t layers) const;

    vk::Context& mCtx;
    mutable std::array<std::unique_ptr<vk::ComputePipeline>, 4> mTrace; // alpha | dynamic
    // One per layer count (1-4), built on first use.
    mutable std::array<std::unique_ptr<vk::ComputePipeline>, kMaxEccentricityLayers> mCompose;
};

} // namespace gt::passes
