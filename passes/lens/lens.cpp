#include "lens/lens.hpp"

#include <algorithm>
#include <cmath>

#include "lens_comp.h"
#include "lens_shared.h"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::lens;

LensPass::LensPass(vk::Context& ctx) : mCtx(ctx) {
    mPipeline = std::make_unique<vk::ComputePipeline>(
        ctx, vk::ComputePipelineDesc{
                 "lens",
                 gt_spv_lens_comp,
                 {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
                 sizeof(sh::LensPush)});
}

LensPass::~LensPass() = default;

rg::TextureId LensPass::add(rg::RenderGraph& graph, rg::TextureId image,
                            const display::LensModel& lens, glm::vec2 centre,
                            bool clampToEdge) const {
    const float aspect =
        static_cast<float>(graph.outputWidth()) / static_cast<float>(graph.outputHeight());
    const float dx = std::max(centre.x, 1.0f - centre.x) * aspect;
    const float dy = std::max(centre.y, 1.0f - centre.y);
    const sh::LensPush push{
        glm::vec4(centre, aspect, std::sqrt(dx * dx + dy * dy)),
        glm::vec4(lens.k1, lens.k2, 1.0f / (1.0f + lens.k1 + lens.k2), clampToEdge ? 1.0f : 0.0f),
        glm::vec4(lens.chroma, 0.0f)};
    struct Data {
        rg::TextureId input, output;
    };
    const auto& data = graph.addPass<Data>(
        "lens",
        [&](rg::PassBuilder& b, Data& d) {
            d.input = b.read(image, rg::Access::StorageRead, VK_FORMAT_R8G8B8A8_UNORM);
            d.output = b.write(b.createTexture("lens.panel", {VK_FORMAT_R8G8B8A8_UNORM}),
                               rg::Access::StorageWrite);
        },
        [ctx = &mCtx, pipeline = mPipeline.get(), push](const rg::PassResources& r, const Data& d,
                                                        VkCommandBuffer cmd) {
            const rg::ResolvedTexture& out = r.texture(d.output);
            vk::DescriptorWriter writer;
            writer.storageImage(sh::kBindingInput, r.texture(d.input).view)
                .storageImage(sh::kBindingOutput, out.view);
            writer.push(*ctx, cmd, *pipeline);
            vk::dispatch(cmd, *pipeline, &push, sizeof(push),
                         (out.width + sh::kGroupX - 1) / sh::kGroupX,
                         (out.height + sh::kGroupY - 1) / sh::kGroupY);
        });
    return data.output;
}

} // namespace gt::passes
