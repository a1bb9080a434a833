#pragma once
// Pass `taa`: temporal anti-aliasing with reprojection, YCoCg variance clipping and history
// rejection on disocclusion and on saccades (gaze jumps). The history lives in TaaHistory, two
// images that swap roles every frame and are imported into each frame's graph.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>

#include <glm/glm.hpp>

#include "render_graph/render_graph.hpp"
#include "scene/scene.hpp"
#include "vk/resources.hpp"

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

class TaaHistory {
public:
    TaaHistory(vk::Context& ctx, uint32_t width, uint32_t height);
    [[nodiscard]] bool valid() const noexcept { return mValid; }
    // Forces the next frame to start afresh (e.g. a saccade event from the eye tracker).
    void invalidate() noexcept { mValid = false; }
    [[nodiscard]] uint32_t framesAccumulated() const noexcept { return mFrames; }

private:
    friend class TaaPass;
    std::array<vk::Image, 2> mImages;
    int mRead = 0; // image holding last frame's output
    bool mValid = false;
    bool mWritten[2] = {false, false};
    uint32_t mFrames = 0;
    scene::Camera mCamera;
    glm::vec2 mGaze{};
};

class TaaPass {
public:
    explicit TaaPass(vk::Context& ctx);
    ~TaaPass();
    // Adds "taa" reading `current` (rgb radiance, a = first-hit distance) and the history,
    // writing the other history image, which it returns. Call history.commit... implicitly:
    // the history advances when the pass is added, so add it once per executed frame.
    rg::TextureId add(rg::RenderGraph& graph, TaaHistory& history, rg::TextureId current,
                      const scene::Camera& camera, glm::vec2 gaze, bool saccade,
                      const TaaSettings& settings = {}) const;

private:
    vk::Context& mCtx;
    std::unique_ptr<vk::ComputePipeline> mPipeline;
};

} // namespace gt::passes
