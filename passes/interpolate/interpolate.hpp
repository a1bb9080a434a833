#pragma once
// Pass `interpolate` (seed 000, 4.3): rebuilds the full image from the sampled points with
// nearest neighbour or the Modified Shepard method over the k nearest points.
#include <cstdint>
#include <memory>
#include <string>

#include <glm/glm.hpp>

#include "render_graph/render_graph.hpp"

namespace gt::vk {
class Context;
class ComputePipeline;
} // namespace gt::vk
namespace gt::foveation {
class GpuPointSet;
}

namespace gt::passes {

// Nearest/Shepard rebuild the image; the others are debug views (--view).
enum class Interpolation { Nearest, Shepard, ViewPoints, ViewCells, ViewSpacing };

struct InterpolateSettings {
    Interpolation method = Interpolation::Nearest;
    uint32_t k = 10;
    float shepardPower = 1.0f; // 1: the thesis's eq. (6); 2: Renka's original
};

[[nodiscard]] Interpolation parseInterpolation(const std::string& name); // nn | msm
[[nodiscard]] Interpolation parseView(const std::string& name); // points | cells | eccentricity

class InterpolatePass {
public:
    explicit InterpolatePass(vk::Context& ctx);
    ~InterpolatePass();
    // Adds "interpolate" reading the samples, writing a new texture "interpolate.radiance".
    rg::TextureId add(rg::RenderGraph& graph, const foveation::GpuPointSet& points,
                      rg::BufferId samples, glm::vec2 gaze, const InterpolateSettings& s) const;

private:
    vk::Context& mCtx;
    std::unique_ptr<vk::ComputePipeline> mPipeline;
};

} // namespace gt::passes
