#include "taa/taa.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include <glm/gtc/packing.hpp>

#include "motion_view_comp.h"
#include "taa_comp.h"
#include "taa_motion_comp.h"
#include "taa_shared.h"
#include "taa_support_comp.h"
#include "taa_support_motion_comp.h"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::taa;

bool taaMustReset(bool historyValid, bool saccade, glm::vec2 gaze, glm::vec2 previousGaze,
                  uint32_t width, const TaaSettings& s) {
    const bool jumped =
        glm::length(gaze - previousGaze) > s.saccadeFraction * static_cast<float>(width);
    return !historyValid || saccade || jumped;
}

TaaPass::TaaPass(vk::Context& ctx) : mCtx(ctx) {
    for (const bool still : {false, true}) {
        // taa.glsl's kStillView (constant_id 3); 0-2 are the motion variants' alone.
        const std::vector<uint32_t> specialization{0u, 0u, 0u, still ? 1u : 0u};
        mPipeline[still] = std::make_unique<vk::ComputePipeline>(
            ctx, vk::ComputePipelineDesc{"taa",
                                         gt_spv_taa_comp,
                                         {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                                          VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                                          VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                                         sizeof(sh::TaaPush),
                                         specialization});
        mSupportPipeline[still] = std::make_unique<vk::ComputePipeline>(
            ctx, vk::ComputePipelineDesc{
                     "taa_support",
                     gt_spv_taa_support_comp,
                     {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                      VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                      VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                     sizeof(sh::TaaPush),
                     specialization});
    }
}

TaaPass::~TaaPass() = default;

const vk::ComputePipeline& TaaPass::motionPipeline(bool support, const TaaSettings& s) const {
    auto& slot = mMotionPipelines[{support, s.currentWeight, s.clipGamma, s.depthTolerance}];
    if (!slot) {
        // Bindings 0-8; without a support, 3-5 are bound but never read.
        const std::vector<VkDescriptorType> bindings(sh::kBindingSignatureOutput + 1,
                                                     VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
        slot = std::make_unique<vk::ComputePipeline>(
            mCtx,
            vk::ComputePipelineDesc{
                support ? "taa_support_motion" : "taa_motion",
                support ? std::span<const uint32_t>(gt_spv_taa_support_motion_comp)
                        : std::span<const uint32_t>(gt_spv_taa_motion_comp),
                bindings,
                sizeof(sh::TaaPush),
                {std::bit_cast<uint32_t>(s.currentWeight), std::bit_cast<uint32_t>(s.clipGamma),
                 std::bit_cast<uint32_t>(s.depthTolerance)}});
    }
    return *slot;
}

bool sameCamera(const shaders::trace::CameraPush& a, const shaders::trace::CameraPush& b) {
    return a.origin == b.origin && a.forward == b.forward && a.right == b.right && a.up == b.up;
}

namespace {

// The frames the history may stand for: the running mean of a still view, else the window
// the fixed current weight averages over.
uint32_t cappedSamples(bool camStill, const TaaSettings& s, const TaaFrameState& st) {
    const auto movingCap =
        std::max(1u, static_cast<uint32_t>(std::lround(1.0f / std::max(s.currentWeight, 1e-3f))));
    const uint32_t cap =
        camStill && st.gazeStill ? std::max(s.maxStillFrames, movingCap) : movingCap;
    return std::min(st.samples, cap - 1);
}
} // namespace

uint32_t TaaPass::nextSamples(const shaders::trace::CameraPush& cur,
                              const shaders::trace::CameraPush& prev, bool reset,
                              const TaaSettings& s, const TaaFrameState& st) {
    if (!s.adaptive) {
        return 0u;
    }
    return reset ? 1u : cappedSamples(sameCamera(cur, prev), s, st) + 1u;
}

namespace {

// The frame's blend weight, clip box, exposure, depth tolerance and eccentric falloff, and the
// cameras, as taa.glsl reads them.
sh::TaaPush taaPush(const rg::RenderGraph& graph, const rg::HistoryTextures& history,
                    const shaders::trace::CameraPush& cur, const shaders::trace::CameraPush& prev,
                    bool reset, const TaaSettings& s, const std::optional<TaaFrameState>& state,
                    const std::optional<TaaSupport>& support,
                    const std::optional<TaaMotion>& motion) {
    const bool still = sameCamera(cur, prev);
    float alpha = s.currentWeight, gamma = s.clipGamma, exposure = 0.0f, radius = 0.0f;
    float depthTolerance = s.depthTolerance;
    glm::vec2 gaze{1.0f};
    if (state && s.adaptive) {
        if (still) {
            // Over a static scene a still camera's history is exact, and the current frame's
            // 3x3 box says little of an interpolated image, whose noise is correlated over a
            // point's neighbourhood: clip loosely (not at all with the gaze still too).
            gamma = state->gazeStill ? 1e30f : s.stillClipGamma;
            depthTolerance = 1e30f; // rays moved in their discs: distances change, not surfaces
        }
        alpha = 1.0f / static_cast<float>(cappedSamples(still, s, *state) + 1);
        exposure = s.displayReferred ? state->exposure : 0.0f;
        if (state->gazeDependent && !(still && state->gazeStill) && s.eccentricRadius > 0.0f) {
            // Negative: the camera moved, and the falloff is the gentler sqrt(d / r).
            radius = (still ? 1.0f : -1.0f) * s.eccentricRadius *
                     static_cast<float>(graph.outputWidth());
            gaze = glm::max(state->gaze, glm::vec2(1.0f)); // no subnormal half pair below
        }
    }
    // The gaze rides in the unused w of currentRight as two halves (taa.comp unpacks them).
    const uint32_t packedGaze = glm::packHalf2x16(gaze);
    float gazeBits = 0.0f;
    std::memcpy(&gazeBits, &packedGaze, sizeof gazeBits);
    return sh::TaaPush{cur.origin,
                       cur.forward,
                       glm::vec4(glm::vec3(cur.right), gazeBits),
                       prev.origin,
                       prev.forward,
                       glm::vec4(glm::vec3(prev.right), radius),
                       glm::vec4(alpha, gamma,
                                 reset || !history.valid || (support && !support->weights.valid) ||
                                         (motion && !motion->signatures.valid)
                                     ? -1.0f
                                     : exposure,
                                 depthTolerance),
                       glm::vec4(cur.right.w, cur.up.w, prev.right.w, prev.up.w)};
}

// Whether the camera stayed and no pixel clips, tests a distance or falls off with eccentricity
// this frame (taa.glsl's conditions on the push, for a scene that does not move): the pipeline
// without that code (kStillView) reads each pixel's own history texel, where the reprojection
// lands up to rounding.
bool stillView(const sh::TaaPush& push, bool sameView) {
    return sameView && push.params.y >= 1e29f && push.params.w >= 1e29f &&
           push.previousRight.w == 0.0f;
}

} // namespace

rg::TextureId TaaPass::add(rg::RenderGraph& graph, const rg::HistoryTextures& history,
                           rg::TextureId current, const shaders::trace::CameraPush& cur,
                           const shaders::trace::CameraPush& prev, bool reset, const TaaSettings& s,
                           const std::optional<TaaFrameState>& state,
                           const std::optional<TaaSupport>& support,
                           const std::optional<TaaMotion>& motion) const {
    const sh::TaaPush push = taaPush(graph, history, cur, prev, reset, s, state, support, motion);
    struct Data {
        rg::TextureId current, history, output;
        std::optional<rg::TextureId> support, weightsPrevious, weightsNext;
        std::optional<rg::TextureId> motion, signaturesPrevious, signaturesNext;
    };
    const auto& data = graph.addPass<Data>(
        "taa",
        [&](rg::PassBuilder& b, Data& d) {
            d.current = b.read(current, rg::Access::StorageRead, VK_FORMAT_R32G32B32A32_SFLOAT);
            d.history = b.read(history.previous, rg::Access::StorageRead);
            d.output = b.write(history.next, rg::Access::StorageWrite);
            if (support) {
                d.support = b.read(support->support, rg::Access::StorageRead, VK_FORMAT_R32_SFLOAT);
                d.weightsPrevious = b.read(support->weights.previous, rg::Access::StorageRead);
                d.weightsNext = b.write(support->weights.next, rg::Access::StorageWrite);
            }
            if (motion) {
                d.motion =
                    b.read(motion->motion, rg::Access::StorageRead, VK_FORMAT_R32G32B32A32_SFLOAT);
                d.signaturesPrevious = b.read(motion->signatures.previous, rg::Access::StorageRead);
                d.signaturesNext = b.write(motion->signatures.next, rg::Access::StorageWrite);
            }
        },
        [ctx = &mCtx,
         pipeline = motion    ? &motionPipeline(support.has_value(), motion->moving)
                    : support ? mSupportPipeline[stillView(push, sameCamera(cur, prev))].get()
                              : mPipeline[stillView(push, sameCamera(cur, prev))].get(),
         push](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            const rg::ResolvedTexture& out = r.texture(d.output);
            vk::DescriptorWriter writer;
            writer.storageImage(sh::kBindingCurrent, r.texture(d.current).view)
                .storageImage(sh::kBindingHistory, r.texture(d.history).view)
                .storageImage(sh::kBindingOutput, out.view);
            if (d.support) {
                writer.storageImage(sh::kBindingSupport, r.texture(*d.support).view)
                    .storageImage(sh::kBindingWeightHistory, r.texture(*d.weightsPrevious).view)
                    .storageImage(sh::kBindingWeightOutput, r.texture(*d.weightsNext).view);
            } else if (d.motion) {
                const VkImageView unread = r.texture(d.current).view;
                writer.storageImage(sh::kBindingSupport, unread)
                    .storageImage(sh::kBindingWeightHistory, unread)
                    .storageImage(sh::kBindingWeightOutput, unread);
            }
            if (d.motion) {
                writer.storageImage(sh::kBindingMotion, r.texture(*d.motion).view)
                    .storageImage(sh::kBindingSignatureHistory,
                                  r.texture(*d.signaturesPrevious).view)
                    .storageImage(sh::kBindingSignatureOutput, r.texture(*d.signaturesNext).view);
            }
            writer.push(*ctx, cmd, *pipeline);
            vk::dispatch(cmd, *pipeline, &push, sizeof(push),
                         (out.width + sh::kGroupX - 1) / sh::kGroupX,
                         (out.height + sh::kGroupY - 1) / sh::kGroupY);
        });
    return data.output;
}

MotionViewPass::MotionViewPass(vk::Context& ctx) : mCtx(ctx) {
    // Bindings 0-6, of which it reads 0 and 6 and writes 2.
    mPipeline = std::make_unique<vk::ComputePipeline>(
        ctx, vk::ComputePipelineDesc{"motion_view", gt_spv_motion_view_comp,
                                     std::vector<VkDescriptorType>(
                                         sh::kBindingMotion + 1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE),
                                     sizeof(sh::TaaPush)});
}

MotionViewPass::~MotionViewPass() = default;

rg::TextureId MotionViewPass::add(rg::RenderGraph& graph, rg::TextureId current,
                                  std::optional<rg::TextureId> motion,
                                  const shaders::trace::CameraPush& cur,
                                  const shaders::trace::CameraPush& prev) const {
    const sh::TaaPush push{cur.origin,
                           cur.forward,
                           cur.right,
                           prev.origin,
                           prev.forward,
                           prev.right,
                           glm::vec4(motion ? 1.0f : 0.0f, 0.0f, 0.0f, 0.0f),
                           glm::vec4(cur.right.w, cur.up.w, prev.right.w, prev.up.w)};
    struct Data {
        rg::TextureId current, output;
        std::optional<rg::TextureId> motion;
    };
    const auto& data = graph.addPass<Data>(
        "motion_view",
        [&](rg::PassBuilder& b, Data& d) {
            d.current = b.read(current, rg::Access::StorageRead, VK_FORMAT_R32G32B32A32_SFLOAT);
            if (motion) {
                d.motion = b.read(*motion, rg::Access::StorageRead, VK_FORMAT_R32G32B32A32_SFLOAT);
            }
            d.output =
                b.write(b.createTexture("motion_view.colour", {VK_FORMAT_R32G32B32A32_SFLOAT}),
                        rg::Access::StorageWrite);
        },
        [ctx = &mCtx, pipeline = mPipeline.get(), push](const rg::PassResources& r, const Data& d,
                                                        VkCommandBuffer cmd) {
            const rg::ResolvedTexture& out = r.texture(d.output);
            const VkImageView radiance = r.texture(d.current).view;
            vk::DescriptorWriter writer;
            writer.storageImage(sh::kBindingCurrent, radiance)
                .storageImage(sh::kBindingOutput, out.view);
            // Bindings 1 and 3-5 are never read; without the scene's motion neither is 6.
            for (const uint32_t unread : {sh::kBindingHistory, sh::kBindingSupport,
                                          sh::kBindingWeightHistory, sh::kBindingWeightOutput}) {
                writer.storageImage(unread, radiance);
            }
            writer.storageImage(sh::kBindingMotion,
                                d.motion ? r.texture(*d.motion).view : radiance);
            writer.push(*ctx, cmd, *pipeline);
            vk::dispatch(cmd, *pipeline, &push, sizeof(push),
                         (out.width + sh::kGroupX - 1) / sh::kGroupX,
                         (out.height + sh::kGroupY - 1) / sh::kGroupY);
        });
    return data.output;
}

} // namespace gt::passes
