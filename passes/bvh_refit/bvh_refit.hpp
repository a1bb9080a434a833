#pragma once
// Pass `bvh_refit`: scene::Bvh::refit on the GPU. The tree's topology is fixed, so its nodes are
// grouped by depth once (bvhRefitLevels) and each frame runs one dispatch per level, deepest
// first: every node of a level reads only its children's boxes, which the level before wrote.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "render_graph/render_graph.hpp"
#include "scene/bvh.hpp"

namespace gt::vk {
class Context;
class ComputePipeline;
} // namespace gt::vk

namespace gt::passes {

// Node indices grouped by depth, the deepest level first: level l is
// order[first[l] .. first[l + 1]).
struct BvhRefitLevels {
    std::vector<uint32_t> order;
    std::vector<uint32_t> first;
    [[nodiscard]] std::size_t levels() const noexcept {
        return first.empty() ? 0 : first.size() - 1;
    }
};
// Children follow their parent in the node array (scene::Bvh's build), so depths are known in
// one forward walk.
[[nodiscard]] BvhRefitLevels bvhRefitLevels(std::span<const scene::BvhNode> nodes);

class BvhRefitPass {
public:
    explicit BvhRefitPass(vk::Context& ctx);
    ~BvhRefitPass();
    // `triangles`: the tree's placed triangles (scene::BvhTriangle, 9 floats each, in
    // Bvh::triangles() order); `order`: levels.order; `nodes`: the tree's nodes, whose bounds
    // are rewritten in place. Returns the refitted nodes.
    rg::BufferId add(rg::RenderGraph& graph, const BvhRefitLevels& levels, rg::BufferId triangles,
                     rg::BufferId order, rg::BufferId nodes) const;

private:
    std::unique_ptr<vk::ComputePipeline> mPipeline;
    vk::Context& mCtx;
};

} // namespace gt::passes
