#pragma once
// Pass `rbf_solve` (thesis, eqs. 7-8): the RBF weights lambda of every sampled point's
// neighbourhood, from the inverses precomputed once per point set (foveation/rbf_inverse.hpp),
// so `interpolate` evaluates eq. (7) per pixel in O(k) instead of solving eq. (8) there.
#include <memory>

#include <glm/glm.hpp>

#include "foveation/interpolation.hpp"
#include "render_graph/render_graph.hpp"

namespace gt::vk {
class Context;
class ComputePipeline;
} // namespace gt::vk
namespace gt::foveation {
class GpuPointSet;
class GpuRbfInverse;
} // namespace gt::foveation

namespace gt::passes {

class RbfSolvePass {
public:
    explicit RbfSolvePass(vk::Context& ctx);
    ~RbfSolvePass();
    // `inverse` must have been built for the settings' k, kernel and shape.
    foveation::RbfWeights add(rg::RenderGraph& graph, const foveation::GpuPointSet& points,
                              const foveation::GpuRbfInverse& inverse, rg::BufferId samples,
                              glm::vec2 gaze, const foveation::InterpolateSettings& s) const;

private:
    vk::Context& mCtx;
    std::unique_ptr<vk::ComputePipeline> mPipeline;
};

} // namespace gt::passes
