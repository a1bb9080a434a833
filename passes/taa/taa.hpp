#pragma once
// Pass `taa`: temporal anti-aliasing with reprojection, YCoCg variance clipping and history
// rejection on disocclusion and on saccades (gaze jumps). The history is the render graph's
// (rg::HistoryPool): last frame's output in, this frame's output out.
#include <cstdint>
#include <memory>

#include <glm/glm.hpp>

#include "render_graph/render_graph.hpp"
#include "trace_shared.h"

namespace gt::vk {
class Context;
class ComputePipeline;
} // namespace gt::vk

namespace gt::passes {

struct TaaSettings {
    float currentWeight = 0.1f;   // blend weight of the new frame
    float clipGamma = 1.0f;       // variance-clipping box half-size in standard deviations
    float depthTolerance = 0.05f; // relative distance change that counts as disocclusion
    // A gaze move larger than this share of the image width is a saccade: history is dropped.
    float saccadeFraction = 1.0f / 16.0f;
};

// Whether a frame must start TAA afresh: no committed history yet, a saccade reported by the eye
// tracker, or a gaze jump larger than `saccadeFraction` of the width since the last frame — so
// the new fovea is sharp at once instead of converging (seed 000, section 3.1).
[[nodiscard]] bool taaMustReset(bool historyValid, bool saccade, glm::vec2 gaze,
                                glm::vec2 previousGaze, uint32_t width, const TaaSettings& s);

class TaaPass {
public:
    explicit TaaPass(vk::Context& ctx);
    ~TaaPass();
    // Adds "taa": reads `current` (rgb radiance, a = first-hit distance) and the history's
    // previous image, reprojected from `previousCamera` to `camera`, and writes the history's
    // next image, which it returns. The graph's HistoryPool commits it once the frame is
    // submitted; with `reset` the history is not read.
    rg::TextureId add(rg::RenderGraph& graph, const rg::HistoryTextures& history,
                      rg::TextureId current, const shaders::trace::CameraPush& camera,
                      const shaders::trace::CameraPush& previousCamera, bool reset,
                      const TaaSettings& settings = {}) const;

private:
    vk::Context& mCtx;
    std::unique_ptr<vk::ComputePipeline> mPipeline;
};

} // namespace gt::passes
