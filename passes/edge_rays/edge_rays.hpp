#pragma once
// Pass `edge_rays`: in a scene that moves, a ray of its own for each pixel of a reconstructed
// image that lies on a moving edge (shaders/edge_rays/edge_rays.glsl), so that TAA pools samples
// taken inside those pixels, as it does at a still edge, instead of the reconstruction's blend
// across the edge.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>

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

// A reconstructed image of a scene that moves: radiance (a = first-hit distance), motion
// (shaders/common/motion.glsl) and, for a reconstruction that reports it, support (taa.glsl).
struct EdgeRaysImage {
    rg::TextureId radiance;
    rg::TextureId motion;
    std::optional<rg::TextureId> support;
};

class EdgeRaysPass {
public:
    explicit EdgeRaysPass(vk::Context& ctx);
    ~EdgeRaysPass();
    // Adds "edge_rays.trace": `in` copied into new textures, with a ray traced through
    // `camera` (jittered inside the pixel by `frameSeed`) where a pixel lies on a moving edge.
    EdgeRaysImage add(rg::RenderGraph& graph, const trace::GpuScene& scene,
                      const shaders::trace::CameraPush& camera, const EdgeRaysImage& in,
                      uint32_t frameSeed) const;

private:
    // Built on first use: with and without the support image, the alpha test (trace.glsl's
    // kAlphaMask) and a scene that moves.
    const vk::ComputePipeline& pipeline(bool support, bool alphaMask, bool dynamic) const;

    vk::Context& mCtx;
    mutable std::array<std::unique_ptr<vk::ComputePipeline>, 8> mPipelines;
};

} // namespace gt::passes
