#pragma once
// Pass `tonemap`: linear radiance (RGBA32F) -> 8-bit sRGB with exposure and an ACES fit.
#include <memory>

#include "render_graph/render_graph.hpp"

namespace gt::vk {
class Context;
class ComputePipeline;
} // namespace gt::vk

namespace gt::passes {

class TonemapPass {
public:
    explicit TonemapPass(vk::Context& ctx);
    ~TonemapPass();
    // Adds "tonemap" reading `radiance`, writing a new RGBA8 texture "tonemap.ldr".
    rg::TextureId add(rg::RenderGraph& graph, rg::TextureId radiance, float exposure) const;

private:
    vk::Context& mCtx;
    std::unique_ptr<vk::ComputePipeline> mPipeline;
};

} // namespace gt::passes
