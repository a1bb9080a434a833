#pragma once
// Pass `point_sample` (seed 000, 4.2): traces R rays inside the disc of every point of the set
// that lands on screen (plus a 10-pixel margin) once shifted to the gaze point.
#include <cstdint>
#include <memory>

#include <glm/glm.hpp>

#include "render_graph/render_graph.hpp"
#include "scene/scene.hpp"

namespace gt::vk {
class Context;
class ComputePipeline;
} // namespace gt::vk
namespace gt::trace {
class GpuScene;
}
namespace gt::foveation {
class GpuPointSet;
}

namespace gt::passes {

inline constexpr float kSampleMargin = 10.0f; // pixels beyond the screen (thesis 4.2)

// Canvas -> screen offset for a gaze point, in whole pixels (the set shifts by the gaze).
[[nodiscard]] glm::vec2 gazeOffset(glm::vec2 gaze, uint32_t displayWidth, uint32_t displayHeight);

class PointSamplePass {
public:
    explicit PointSamplePass(vk::Context& ctx);
    ~PointSamplePass();
    // Adds "point_sample" writing a new buffer "point_sample.samples" (one vec4 per point).
    rg::BufferId add(rg::RenderGraph& graph, const trace::GpuScene& scene,
                     const scene::Camera& camera, const foveation::GpuPointSet& points,
                     glm::vec2 gaze, uint32_t raysPerPoint) const;

private:
    vk::Context& mCtx;
    std::unique_ptr<vk::ComputePipeline> mPipeline;
};

} // namespace gt::passes
