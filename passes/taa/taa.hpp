#pragma once
// Pass `taa`: temporal anti-aliasing with reprojection, YCoCg variance clipping and history
// rejection on disocclusion and on saccades (gaze jumps). The history is the render graph's
// (rg::HistoryPool): last frame's output in, this frame's output out.
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <tuple>

#include <glm/glm.hpp>

#include "render_graph/render_graph.hpp"
#include "trace_shared.h"

namespace gt::vk {
class Context;
class ComputePipeline;
} // namespace gt::vk

namespace gt::passes {

struct TaaSettings {
    float currentWeight = 0.1f; // blend weight of the new frame
    float clipGamma = 1.0f;     // variance-clipping box half-size in standard deviations
    // The same with the camera still and the gaze moving (this frame's camera equal to the
    // last one's): over a static scene the history is then exact, and what changes from frame
    // to frame is the method's own sampling (a point set following the gaze). A wider box lets
    // the history average that instead of flickering. With the gaze still too, nothing clips.
    float stillClipGamma = 4.0f;
    // With camera and gaze still, the history becomes the running mean of the frames (current
    // weight 1 / (n + 1)) up to this many: a still view with rays that change every frame
    // converges instead of flickering.
    uint32_t maxStillFrames = 64;
    // A foveated view with the camera still and the gaze moving (smooth pursuit): beyond this
    // share r of the image width from the gaze, the current weight falls and the clipping box
    // grows with the distance d as r / d, so the sparse periphery sliding under a still scene
    // is averaged instead of flickering while the fovea stays responsive; with the camera
    // moving, by the gentler sqrt(r / d), as the history is only reprojected. 0: off.
    float eccentricRadius = 0.05f;
    // Blend in display-referred space (taa.comp's toDisplay: Reinhard at the view's exposure
    // e, c / (1 + e L), then a 1/2.2 power), so a frame moves a pixel by at most the blend
    // weight of its displayed range; a linear blend of HDR radiance lets one lamp sample flash
    // a dark pixel, where the display's encoding is steep.
    bool displayReferred = true;
    // false: the fixed blend of the thesis's TAA (currentWeight, clipGamma, depthTolerance, linear
    // radiance, whatever moved), ignoring the frame state and the settings above.
    bool adaptive = true;
    // With camera and gaze still and a method that reports per pixel how near this frame's
    // samples fell (TaaPass::add's support), each frame counts by that nearness.
    bool supportWeighted = true;
    float depthTolerance = 0.05f; // relative distance change that counts as disocclusion
    // A gaze move larger than this share of the image width is a saccade: history is dropped.
    float saccadeFraction = 1.0f / 16.0f;
};

// The same pinhole (position, orientation, frustum): nothing in a static scene moved.
[[nodiscard]] bool sameCamera(const shaders::trace::CameraPush& a,
                              const shaders::trace::CameraPush& b);

// What the renderer tracks of a view's frames that sets how much the history counts.
struct TaaFrameState {
    float exposure = 0.0f;      // display-referred blending at this exposure (0: linear)
    glm::vec2 gaze{};           // pixels
    bool gazeDependent = false; // the image's sampling follows the gaze (a foveated method)
    bool gazeStill = false;     // the gaze has not moved since the last frame
    uint32_t samples = 0;       // frames the history holds (0 after a reset)
};

// Whether a frame must start TAA afresh: no committed history yet, a saccade reported by the eye
// tracker, or a gaze jump larger than `saccadeFraction` of the width since the last frame — so
// the new fovea is sharp at once instead of converging (thesis, section 3.1).
[[nodiscard]] bool taaMustReset(bool historyValid, bool saccade, glm::vec2 gaze,
                                glm::vec2 previousGaze, uint32_t width, const TaaSettings& s);

// For a method that reports how directly each pixel was sampled (render::MethodImage::support):
// that image, and the history of the per-pixel weight sums the still view's weighted running
// mean keeps (taa.glsl).
struct TaaSupport {
    rg::TextureId support;
    rg::HistoryTextures weights; // R32_SFLOAT, the view's size
};

// For a method whose scene moves (trace::GpuScene::dynamic()): per pixel the first hit's
// motion (rgba32f: xyz = its world position one frame ago minus now, w = its signature code,
// shaders/common/motion.glsl), and the history of the signatures TAA's output shows (taa.glsl).
// A pixel whose hit moved blends as on a moving camera, with `moving`'s currentWeight,
// clipGamma and depthTolerance (the view's TaaSettings, before any still-view adjustment).
// The format of TaaMotion::signatures: the signature code and the history's frame count in one
// texel (shaders/shared/taa_shared.h, kHistoryFramesShift).
inline constexpr VkFormat kTaaSignatureFormat = VK_FORMAT_R32_UINT;

struct TaaMotion {
    rg::TextureId motion;
    rg::HistoryTextures signatures; // kTaaSignatureFormat, the view's size
    TaaSettings moving;
};

class TaaPass {
public:
    explicit TaaPass(vk::Context& ctx);
    ~TaaPass();
    // Adds "taa": reads `current` (rgb radiance, a = first-hit distance) and the history's
    // previous image, reprojected from `previousCamera` to `camera`, and writes the history's
    // next image, which it returns. The graph's HistoryPool commits it once the frame is
    // submitted; with `reset` the history is not read. With `state`, the blend follows the
    // view's frames (TaaSettings); without, it is the fixed settings.currentWeight, linear.
    rg::TextureId add(rg::RenderGraph& graph, const rg::HistoryTextures& history,
                      rg::TextureId current, const shaders::trace::CameraPush& camera,
                      const shaders::trace::CameraPush& previousCamera, bool reset,
                      const TaaSettings& settings = {},
                      const std::optional<TaaFrameState>& state = std::nullopt,
                      const std::optional<TaaSupport>& support = std::nullopt,
                      const std::optional<TaaMotion>& motion = std::nullopt) const;
    // The history's frame count after this frame (TaaFrameState::samples of the next one).
    [[nodiscard]] static uint32_t nextSamples(const shaders::trace::CameraPush& camera,
                                              const shaders::trace::CameraPush& previousCamera,
                                              bool reset, const TaaSettings& settings,
                                              const TaaFrameState& state);

private:
    // With motion: per support and the blend of a pixel whose hit moved (TaaMotion::moving's
    // current weight, clip gamma and depth tolerance: specialisation constants), built on
    // first use.
    const vk::ComputePipeline& motionPipeline(bool support, const TaaSettings& moving) const;

    vk::Context& mCtx;
    // Indexed by whether the view is still (taa.glsl's kStillView).
    std::array<std::unique_ptr<vk::ComputePipeline>, 2> mPipeline, mSupportPipeline;
    mutable std::map<std::tuple<bool, float, float, float>, std::unique_ptr<vk::ComputePipeline>>
        mMotionPipelines;
};

// Debug view `motion` (--view motion): each pixel's screen-space motion since the last frame
// as colour (shaders/taa/motion_view.comp), from `current` (a = first-hit distance), the scene's
// `motion` when it moves (else the camera's alone) and both cameras.
class MotionViewPass {
public:
    explicit MotionViewPass(vk::Context& ctx);
    ~MotionViewPass();
    // Adds "motion_view" writing a new texture "motion_view.colour" of the output's size.
    rg::TextureId add(rg::RenderGraph& graph, rg::TextureId current,
                      std::optional<rg::TextureId> motion, const shaders::trace::CameraPush& camera,
                      const shaders::trace::CameraPush& previousCamera) const;

private:
    vk::Context& mCtx;
    std::unique_ptr<vk::ComputePipeline> mPipeline;
};

} // namespace gt::passes
