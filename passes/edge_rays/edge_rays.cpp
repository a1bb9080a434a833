#include "edge_rays/edge_rays.hpp"

#include "edge_rays_comp.h"
#include "edge_rays_shared.h"
#include "edge_rays_support_comp.h"
#include "trace/gpu_scene.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::edge_rays;

EdgeRaysPass::EdgeRaysPass(vk::Context& ctx) : mCtx(ctx) {}

EdgeRaysPass::~EdgeRaysPass() = default;

const vk::ComputePipeline& EdgeRaysPass::pipeline(bool support, bool alphaMask,
                                                  bool dynamic) const {
    auto& slot = mPipelines[(support ? 1 : 0) + (alphaMask ? 2 : 0) + (dynamic ? 4 : 0)];
    if (!slot) {
        // Bindings 9-14 in order (edge_rays_shared.h); without support, 11 and 14 are declared
        // but the shader never uses them.
        const std::vector<VkDescriptorType> bindings = trace::tracingBindings(
            {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
             VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
             VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE});
        slot = std::make_unique<vk::ComputePipeline>(
            mCtx, vk::ComputePipelineDesc{
                      "edge_rays.trace",
                      support ? std::span<const uint32_t>(gt_spv_edge_rays_support_comp)
                              : std::span<const uint32_t>(gt_spv_edge_rays_comp),
                      bindings, sizeof(sh::EdgeRaysPush),
                      trace::tracingSpecialization({alphaMask ? 1u : 0u}, dynamic)});
    }
    return *slot;
}

EdgeRaysImage EdgeRaysPass::add(rg::RenderGraph& graph, const trace::GpuScene& scene,
                                const shaders::trace::CameraPush& cam, const EdgeRaysImage& in,
                                uint32_t frameSeed) const {
    struct Data {
        EdgeRaysImage in, out;
    };
    const uint32_t w = graph.outputWidth(), h = graph.outputHeight();
    const sh::EdgeRaysPush push{cam.origin, cam.forward, cam.right, cam.up,
                                glm::uvec4(w, h, 0u, frameSeed)};
    const bool support = in.support.has_value();
    const auto& data = graph.addPass<Data>(
        "edge_rays.trace",
        [&](rg::PassBuilder& b, Data& d) {
            const VkFormat rgba = VK_FORMAT_R32G32B32A32_SFLOAT;
            d.in.radiance = b.read(in.radiance, rg::Access::StorageRead, rgba);
            d.in.motion = b.read(in.motion, rg::Access::StorageRead, rgba);
            d.out.radiance =
                b.write(b.createTexture("edge_rays.radiance", {rgba}), rg::Access::StorageWrite);
            d.out.motion =
                b.write(b.createTexture("edge_rays.motion", {rgba}), rg::Access::StorageWrite);
            if (support) {
                d.in.support = b.read(*in.support, rg::Access::StorageRead, VK_FORMAT_R32_SFLOAT);
                d.out.support =
                    b.write(b.createTexture("edge_rays.support", {VK_FORMAT_R32_SFLOAT}),
                            rg::Access::StorageWrite);
            }
        },
        [ctx = &mCtx, pipeline = &pipeline(support, scene.alphaMasked(), scene.dynamic()),
         scene = &scene, push](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            const VkImageView radiance = r.texture(d.in.radiance).view;
            const VkImageView output = r.texture(d.out.radiance).view;
            trace::dispatchImageTrace(
                *ctx, cmd, *pipeline, *scene,
                {{sh::kBindingRadiance, radiance},
                 {sh::kBindingMotion, r.texture(d.in.motion).view},
                 {sh::kBindingSupport, d.in.support ? r.texture(*d.in.support).view : radiance},
                 {sh::kBindingRadianceOutput, output},
                 {sh::kBindingMotionOutput, r.texture(d.out.motion).view},
                 {sh::kBindingSupportOutput,
                  d.out.support ? r.texture(*d.out.support).view : output}},
                std::as_bytes(std::span(&push, 1)), {push.params.x, push.params.y},
                {sh::kGroupSizeX, sh::kGroupSizeY});
        });
    return data.out;
}

} // namespace gt::passes
