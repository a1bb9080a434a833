#include "tonemap/tonemap.hpp"

#include "tonemap_comp.h"
#include "tonemap_shared.h"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::tonemap;

TonemapPass::TonemapPass(vk::Context& ctx) : mCtx(ctx) {
    mPipeline = std::make_unique<vk::ComputePipeline>(
        ctx, vk::ComputePipelineDesc{
                 "tonemap",
                 gt_spv_tonemap_comp,
                 {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                 sizeof(sh::TonemapPush)});
}

TonemapPass::~TonemapPass() = default;

rg::TextureId TonemapPass::add(rg::RenderGraph& graph, rg::TextureId radiance,
                               float exposure) const {
    struct Data {
        rg::TextureId input, output;
    };
    const sh::TonemapPush push{glm::vec4(exposure, 0, 0, 0)};
    const auto& data = graph.addPass<Data>(
        "tonemap",
        [&](rg::PassBuilder& b, Data& d) {
            d.input = b.read(radiance, rg::Access::StorageRead, VK_FORMAT_R32G32B32A32_SFLOAT);
            d.output = b.write(b.createTexture("tonemap.ldr", {VK_FORMAT_R8G8B8A8_UNORM}),
                               rg::Access::StorageWrite);
        },
        [ctx = &mCtx, pipeline = mPipeline.get(), push](const rg::PassResources& r, const Data& d,
                                                        VkCommandBuffer cmd) {
            const rg::ResolvedTexture& out = r.texture(d.output);
            vk::DescriptorWriter writer;
            writer.storageImage(sh::kBindingInput, r.texture(d.input).view)
                .storageImage(sh::kBindingOutput, out.view);
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline->handle());
            writer.push(*ctx, cmd, *pipeline);
            vk::dispatch(cmd, *pipeline, &push, sizeof(push),
                         (out.width + sh::kGroupSizeX - 1) / sh::kGroupSizeX,
                         (out.height + sh::kGroupSizeY - 1) / sh::kGroupSizeY);
        });
    return data.output;
}

} // namespace gt::passes
