#include "taa/taa.hpp"

#include "taa_comp.h"
#include "taa_shared.h"
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
    mPipeline = std::make_unique<vk::ComputePipeline>(
        ctx,
        vk::ComputePipelineDesc{"taa",
                                gt_spv_taa_comp,
                                {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                                 VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                                sizeof(sh::TaaPush)});
}

TaaPass::~TaaPass() = default;

rg::TextureId TaaPass::add(rg::RenderGraph& graph, const rg::HistoryTextures& history,
                           rg::TextureId current, const shaders::trace::CameraPush& cur,
                           const shaders::trace::CameraPush& prev, bool reset,
                           const TaaSettings& s) const {
    const sh::TaaPush push{cur.origin,
                           cur.forward,
                           cur.right,
                           prev.origin,
                           prev.forward,
                           prev.right,
                           glm::vec4(s.currentWeight, s.clipGamma,
                                     reset || !history.valid ? 1.0f : 0.0f, s.depthTolerance),
                           glm::vec4(cur.right.w, cur.up.w, prev.right.w, prev.up.w)};
    struct Data {
        rg::TextureId current, history, output;
    };
    const auto& data = graph.addPass<Data>(
        "taa",
        [&](rg::PassBuilder& b, Data& d) {
            d.current = b.read(current, rg::Access::StorageRead, VK_FORMAT_R32G32B32A32_SFLOAT);
            d.history = b.read(history.previous, rg::Access::StorageRead);
            d.output = b.write(history.next, rg::Access::StorageWrite);
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
    return data.output;
}

} // namespace gt::passes
