#include "taa/taa.hpp"

#include "taa_comp.h"
#include "taa_shared.h"
#include "trace/gpu_scene.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::taa;

TaaHistory::TaaHistory(vk::Context& ctx, uint32_t width, uint32_t height)
    : mImages{vk::Image(ctx, {width, height, VK_FORMAT_R32G32B32A32_SFLOAT,
                              VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                              "taa.history0"}),
              vk::Image(ctx, {width, height, VK_FORMAT_R32G32B32A32_SFLOAT,
                              VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                              "taa.history1"})} {}

TaaPass::TaaPass(vk::Context& ctx) : mCtx(ctx) {
    mPipeline = std::make_unique<vk::ComputePipeline>(
        ctx,
        vk::ComputePipelineDesc{"taa",
                                gt_spv_taa_comp,
                                {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                                 VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                                sizeof(sh::TaaPush)});
}

TaaPass::~TaaPass() = default;

rg::TextureId TaaPass::add(rg::RenderGraph& graph, TaaHistory& h, rg::TextureId current,
                           const scene::Camera& camera, glm::vec2 gaze, bool saccade,
                           const TaaSettings& s) const {
    const uint32_t w = graph.outputWidth(), ht = graph.outputHeight();
    const float aspect = static_cast<float>(w) / static_cast<float>(ht);
    const bool jumped = glm::length(gaze - h.mGaze) > s.saccadeFraction * static_cast<float>(w);
    const bool reset = !h.mValid || saccade || jumped;
    const auto cur = trace::cameraPush(camera, aspect);
    const auto prev = trace::cameraPush(h.mValid ? h.mCamera : camera, aspect);
    const sh::TaaPush push{
        cur.origin,
        cur.forward,
        cur.right,
        prev.origin,
        prev.forward,
        prev.right,
        glm::vec4(s.currentWeight, s.clipGamma, reset ? 1.0f : 0.0f, s.depthTolerance)};
    const int readIndex = h.mRead, writeIndex = 1 - h.mRead;
    auto import = [&](int i, const char* name) {
        const vk::Image& img = h.mImages[static_cast<std::size_t>(i)];
        return graph.importTexture(
            name, {img.handle(), img.view(), VK_FORMAT_R32G32B32A32_SFLOAT, w, ht,
                   h.mWritten[i] ? std::optional(rg::Access::StorageWrite) : std::nullopt,
                   // Whatever reads the result this frame (tonemap, a readback), leave the
                   // image in GENERAL, the layout the next frame's import declares.
                   rg::Access::StorageRead});
    };
    const rg::TextureId historyIn = import(readIndex, "taa.history");
    const rg::TextureId historyOut = import(writeIndex, "taa.output");
    struct Data {
        rg::TextureId current, history, output;
    };
    const auto& data = graph.addPass<Data>(
        "taa",
        [&](rg::PassBuilder& b, Data& d) {
            d.current = b.read(current, rg::Access::StorageRead, VK_FORMAT_R32G32B32A32_SFLOAT);
            d.history = b.read(historyIn, rg::Access::StorageRead);
            d.output = b.write(historyOut, rg::Access::StorageWrite);
        },
        [ctx = &mCtx, pipeline = mPipeline.get(), push](const rg::PassResources& r, const Data& d,
                                                        VkCommandBuffer cmd) {
            const rg::ResolvedTexture& out = r.texture(d.output);
            vk::DescriptorWriter writer;
            writer.storageImage(sh::kBindingCurrent, r.texture(d.current).view)
                .storageImage(sh::kBindingHistory, r.texture(d.history).view)
                .storageImage(sh::kBindingOutput, out.view);
            writer.push(*ctx, cmd, *pipeline);
            vk::dispatch(cmd, *pipeline, &push, sizeof(push),
                         (out.width + sh::kGroupX - 1) / sh::kGroupX,
                         (out.height + sh::kGroupY - 1) / sh::kGroupY);
        });
    // Advance the history for the next frame (the caller executes this graph before the next).
    h.mWritten[writeIndex] = true;
    h.mRead = writeIndex;
    h.mValid = true;
    h.mFrames = reset ? 1 : h.mFrames + 1;
    h.mCamera = camera;
    h.mGaze = gaze;
    return data.output;
}

} // namespace gt::passes
