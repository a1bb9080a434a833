#pragma once
// Pass `interpolate` (thesis, 4.3): rebuilds the full image from the sampled points with
// nearest neighbour, the Modified Shepard method over the k nearest points, or radial basis
// functions from the weights pass `rbf_solve` wrote.
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>

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
class GpuPixelKnnTable;
class GpuRbfPixelWeights;
} // namespace gt::foveation

namespace gt::passes {

using foveation::InterpolateSettings;
using foveation::Interpolation;
using foveation::KnnIndex;
using foveation::RbfKernel;
using foveation::RbfWeights;
using foveation::readsNeighbourIndex;
using foveation::usesPixelTable;
using foveation::usesRbfSolve;

// What a method reads besides the samples, prepared by the caller for the same settings:
// rbf_solve's weights (RBF over the neighbour lists), the k-NN table (usesPixelTable), and the
// per-pixel RBF weights (RBF with the table; built for the table's k).
struct InterpolateInputs {
    std::optional<RbfWeights> lambdas;
    const foveation::GpuPixelKnnTable* table = nullptr;
    const foveation::GpuRbfPixelWeights* rbfWeights = nullptr;
};

// What interpolate writes: the radiance (rgb; a = the nearest sample's first-hit distance) and
// per pixel the distance to the sample it took most from, in units of that point's spacing p —
// how directly this frame saw the pixel, which TAA weighs the frame by on a still view.
// In a scene that moves, also per pixel the motion of its nearest sample (rgba32f, the samples'
// layout: shaders/common/motion.glsl).
struct InterpolatedImage {
    rg::TextureId radiance, support;
    std::optional<rg::TextureId> motion;
};

class InterpolatePass {
public:
    explicit InterpolatePass(vk::Context& ctx);
    ~InterpolatePass();
    // Adds "interpolate" reading the samples, writing new textures "interpolate.radiance" and
    // "interpolate.support"; before it, for every method but nearest neighbour,
    // "interpolate.sites". `in` must hold what the settings need (see InterpolateInputs).
    // With `sampleMotion` (point_sample's, a scene that moves) also "interpolate.motion".
    InterpolatedImage add(rg::RenderGraph& graph, const foveation::GpuPointSet& points,
                          rg::BufferId samples, glm::vec2 gaze, const InterpolateSettings& s,
                          const InterpolateInputs& in = {},
                          std::optional<rg::BufferId> sampleMotion = std::nullopt) const;

    // The shader's specialisation (shaders/interpolate/interpolate.comp): the method, whether it
    // reads the k-NN table, whether that table is flat, whether it writes motion (a scene that
    // moves), and whether nearest neighbour's nearest point is always a sampled one.
    using Variant = std::tuple<uint32_t, bool, bool, bool, bool>;

private:
    const vk::ComputePipeline& pipeline(const Variant& variant) const;
    // Adds "interpolate.sites": every point of the set on the screen this frame (`offset`: the
    // canvas -> screen offset of the gaze), moved as the settings say (a new buffer of the set's
    // size, vec4 x, y, spacing, 0).
    rg::BufferId addSites(rg::RenderGraph& graph, const foveation::GpuPointSet& points,
                          glm::vec2 offset, const InterpolateSettings& s) const;

    vk::Context& mCtx;
    std::unique_ptr<vk::ComputePipeline> mSites;
    // The common variants are built with the pass; the others on first use.
    mutable std::map<Variant, std::unique_ptr<vk::ComputePipeline>> mPipelines;
};

} // namespace gt::passes
