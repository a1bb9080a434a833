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

#include <glm/glm.hpp>

#include "foveation/rbf_system.hpp"
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

// Nearest/Shepard rebuild the image; the others are debug views (--view).
enum class Interpolation { Nearest, Shepard, Rbf, ViewPoints, ViewCells, ViewSpacing };
// The engine's kernel type, so that settings pass to the RBF builders unconverted.
using RbfKernel = foveation::RbfKernelType;
// Where Modified Shepard and RBF find a pixel's k nearest points. PixelTable (the default): the
// thesis's table of the k nearest per canvas pixel, exact, 2-2.5x faster per frame than the
// lists on lavapipe, but 29.5 MB per neighbour (590 MB at k = 20) and seconds to build; RBF
// adds as much again for its per-pixel weights (rbf_pixel_weights.hpp) and then costs no more
// than Modified Shepard. NeighbourLists: the nearest point per canvas pixel plus that point's
// 20 neighbours (75.6 MB for fove), exact at k <= 7 and close at k = 20; RBF then solves per
// point each frame (rbf_solve). Nearest neighbour always uses the nearest-point array (the
// thesis's table at k = 1).
enum class KnnIndex { NeighbourLists, PixelTable };

struct InterpolateSettings {
    Interpolation method = Interpolation::Nearest;
    uint32_t k = 10;
    float shepardPower = 2.0f;                  // 1: the thesis's eq. (6); 2: Renka's original
    RbfKernel kernel = RbfKernel::Multiquadric; // thesis eq. (10); Gaussian is eq. (9)
    float rbfShape = 1.0f;                      // c, in units of the point's spacing p
    KnnIndex knn = KnnIndex::PixelTable;        // where msm finds its k neighbours
    // Blend in display-referred space at this exposure (the view's): T(c) = c / (1 + e L(c)),
    // mapped back after (interpolate.comp). 0: linear radiance, as the thesis. Modified Shepard
    // and RBF with the pixel table; rbf_solve's per-point weights stay linear.
    float displayExposure = 0.0f;
    // Geometry-aware Modified Shepard: neighbours whose first-hit distance differs from the
    // nearest sample's by more than about this share of it lose their weight. 0: off (the
    // thesis).
    float edgeTolerance = 0.1f;
    // Colour-guided Modified Shepard: neighbours whose display-referred luminance differs from
    // the nearest sample's by more than about this lose their weight. 0: off (the thesis).
    float rangeSigma = 0.1f;
    // The frame whose moved sites point_sample traced (site_jitter.glsl), set per frame by the
    // method: Modified Shepard (and nearest neighbour, if given) blend from them. 0: the fixed
    // sites.
    uint32_t siteFrame = 0;
    float siteJitter = 0.0f; // how far they moved, as a share of their spacing
};

// The RBF weights rbf_solve wrote (one buffer per colour channel).
struct RbfWeights {
    rg::BufferId r, g, b;
};

// What a method reads besides the samples, prepared by the caller for the same settings:
// rbf_solve's weights (RBF over the neighbour lists), the k-NN table (usesPixelTable), and the
// per-pixel RBF weights (RBF with the table; built for the table's k).
struct InterpolateInputs {
    std::optional<RbfWeights> lambdas;
    const foveation::GpuPixelKnnTable* table = nullptr;
    const foveation::GpuRbfPixelWeights* rbfWeights = nullptr;
};

[[nodiscard]] Interpolation parseInterpolation(const std::string& name); // nn | msm | rbf
[[nodiscard]] RbfKernel parseKernel(const std::string& name);            // multiquadric | gaussian
[[nodiscard]] KnnIndex parseKnnIndex(const std::string& name);           // lists | table
[[nodiscard]] bool usesPixelTable(const InterpolateSettings& s);         // msm/rbf with PixelTable
[[nodiscard]] bool usesRbfSolve(const InterpolateSettings& s);           // rbf with NeighbourLists
[[nodiscard]] Interpolation parseView(const std::string& name); // points | cells | eccentricity

// What interpolate writes: the radiance (rgb; a = the nearest sample's first-hit distance) and
// per pixel the distance to the sample it took most from, in units of that point's spacing p —
// how directly this frame saw the pixel, which TAA weighs the frame by on a still view.
struct InterpolatedImage {
    rg::TextureId radiance, support;
};

class InterpolatePass {
public:
    explicit InterpolatePass(vk::Context& ctx);
    ~InterpolatePass();
    // Adds "interpolate" reading the samples, writing new textures "interpolate.radiance" and
    // "interpolate.support". `in` must hold what the settings need (see InterpolateInputs).
    InterpolatedImage add(rg::RenderGraph& graph, const foveation::GpuPointSet& points,
                          rg::BufferId samples, glm::vec2 gaze, const InterpolateSettings& s,
                          const InterpolateInputs& in = {}) const;

private:
    vk::Context& mCtx;
    // Specialised per (method, reads the k-NN table): see shaders/interpolate/interpolate.comp.
    std::map<std::pair<uint32_t, bool>, std::unique_ptr<vk::ComputePipeline>> mPipelines;
};

} // namespace gt::passes
