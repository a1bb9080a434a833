#include "bvh_refit/bvh_refit.hpp"

#include "bvh_refit_comp.h"
#include "bvh_refit_shared.h"
#include "core/error.hpp"
#include "vk/context.hpp"
#include "vk/pipeline.hpp"

namespace gt::passes {

namespace sh = shaders::bvh_refit;

BvhRefitLevels bvhRefitLevels(std::span<const scene::BvhNode> nodes) {
    std::vector<uint32_t> depth(nodes.size(), 0);
    uint32_t deepest = 0;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        deepest = std::max(deepest, depth[i]);
        if (nodes[i].count > 0) continue;
        const uint32_t left = nodes[i].leftFirst;
        if (left <= i || left + 1 >= nodes.size()) {
            throw ArgumentError("bvh_refit: node " + std::to_string(i) +
                                " has children that do not follow it");
        }
        depth[left] = depth[left + 1] = depth[i] + 1;
    }
    BvhRefitLevels levels;
    levels.order.reserve(nodes.size());
    for (uint32_t d = deepest + 1; d-- > 0;) {
        levels.first.push_back(static_cast<uint32_t>(levels.order.size()));
        for (uint32_t i = 0; i < nodes.size(); ++i)
            if (depth[i] == d) levels.order.push_back(i);
    }
    levels.first.push_back(static_cast<uint32_t>(levels.order.size()));
    return levels;
}

BvhRefitPass::BvhRefitPass(vk::Context& ctx) : mCtx(ctx) {
    mPipeline = std::make_unique<vk::ComputePipeline>(
        ctx, vk::ComputePipelineDesc{
                 "bvh_refit",
                 gt_spv_bvh_refit_comp,
                 {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                  VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                 sizeof(sh::BvhRefitPush)});
}

BvhRefitPass::~BvhRefitPass() = default;

namespace {

// The levels run in one pass, so the graph cannot order them: each level's writes of the boxes
// (which the next level reads) and of the node bounds are made visible here.
void levelBarrier(VkCommandBuffer cmd, VkBuffer boxes, VkBuffer nodes) {
    VkBufferMemoryBarrier2 barriers[2]{};
    const VkBuffer buffers[2]{boxes, nodes};
    for (int i = 0; i < 2; ++i) {
        barriers[i].sType = VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2;
        barriers[i].srcStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
        barriers[i].srcAccessMask = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
        barriers[i].dstStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
        barriers[i].dstAccessMask =
            VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
        barriers[i].srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        barriers[i].dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        barriers[i].buffer = buffers[i];
        barriers[i].size = VK_WHOLE_SIZE;
    }
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.bufferMemoryBarrierCount = 2;
    dep.pBufferMemoryBarriers = barriers;
    vkCmdPipelineBarrier2(cmd, &dep);
}

} // namespace

rg::BufferId BvhRefitPass::add(rg::RenderGraph& graph, const BvhRefitLevels& levels,
                               rg::BufferId triangles, rg::BufferId order,
                               rg::BufferId nodes) const {
    if (levels.levels() == 0) throw ArgumentError("bvh_refit: a tree without nodes");
    struct Data {
        rg::BufferId triangles, order, nodes, boxes;
    };
    const VkDeviceSize boxBytes = 2 * sizeof(glm::vec4) * levels.order.size();
    const auto& data = graph.addPass<Data>(
        "bvh_refit",
        [&](rg::PassBuilder& b, Data& d) {
            d.triangles = b.read(triangles, rg::Access::StorageRead);
            d.order = b.read(order, rg::Access::StorageRead);
            d.nodes = b.write(nodes, rg::Access::StorageReadWrite);
            // Scratch: every level writes its boxes before the next reads them (levelBarrier).
            d.boxes =
                b.write(b.createBuffer("bvh_refit.boxes", {boxBytes}), rg::Access::StorageWrite);
        },
        [ctx = &mCtx, pipeline = mPipeline.get(),
         first = levels.first](const rg::PassResources& r, const Data& d, VkCommandBuffer cmd) {
            vk::DescriptorWriter writer;
            writer.storageBuffer(sh::kBindingRefitTriangles, r.buffer(d.triangles))
                .storageBuffer(sh::kBindingRefitOrder, r.buffer(d.order))
                .storageBuffer(sh::kBindingRefitNodes, r.buffer(d.nodes))
                .storageBuffer(sh::kBindingRefitBoxes, r.buffer(d.boxes));
            writer.push(*ctx, cmd, *pipeline);
            for (std::size_t l = 0; l + 1 < first.size(); ++l) {
                if (l > 0) levelBarrier(cmd, r.buffer(d.boxes), r.buffer(d.nodes));
                const sh::BvhRefitPush push{glm::uvec4(first[l], first[l + 1] - first[l], 0, 0)};
                vk::dispatch(cmd, *pipeline, &push, sizeof(push),
                             (push.level.y + sh::kRefitGroupSize - 1) / sh::kRefitGroupSize, 1);
            }
        });
    return data.nodes;
}

} // namespace gt::passes
