#pragma once
// Pass `lens`: an HMD eye's image pre-distorted for its lens (barrel, with per-channel radial
// scales for chromatic aberration), so that the pincushion lens shows it straight. The model and
// its parameters: engine/display/hmd_profile.hpp.
#include <memory>

#include <glm/glm.hpp>

#include "display/hmd_profile.hpp"
#include "render_graph/render_graph.hpp"

namespace gt::vk {
class Context;
class ComputePipeline;
} // namespace gt::vk

namespace gt::passes {

class LensPass {
public:
    explicit LensPass(vk::Context& ctx);
    ~LensPass();
    // Adds "lens" reading `image` (RGBA8, sRGB-encoded), writing a new same-sized RGBA8 texture
    // "lens.panel". `centre`: the lens centre in normalised image coordinates.
    // `clampToEdge`: samples past the image's edge repeat it (the input is already the panel's
    // image and only the chromatic shift remains) instead of showing black.
    rg::TextureId add(rg::RenderGraph& graph, rg::TextureId image, const display::LensModel& lens,
                      glm::vec2 centre, bool clampToEdge = false) const;

private:
    vk::Context& mCtx;
    std::unique_ptr<vk::ComputePipeline> mPipeline;
};

} // namespace gt::passes
