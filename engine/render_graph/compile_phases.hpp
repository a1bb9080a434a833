#pragma once
// RenderGraph::compile() as a pipeline of phases, each pure CPU work from plain data to plain
// data (the split of Filament's FrameGraph::compile and Granite's RenderGraph::bake):
//   dependencies -> cull -> order -> lifetimes -> barriers.
// Each phase can be run and checked on its own; compile() calls them in turn and assembles the
// CompiledGraph. Every phase that finds a broken declaration throws GraphError.
#include <cstdint>
#include <map>
#include <set>
#include <span>
#include <utility>
#include <vector>

#include "render_graph/graph_declarations.hpp"

namespace gt::rg::detail {

using VersionKey = std::pair<uint32_t, uint32_t>; // (resource, version)

// Who writes each version of each resource, and which passes must run before which: a reader
// after the writer of its version (RAW), the writer of version v+1 after the readers of v (WAR)
// and after the writer of v (WAW), and explicit dependsOn() orders.
struct Dependencies {
    std::map<VersionKey, uint32_t> writer;
    std::vector<std::set<uint32_t>> preds; // per pass, in declaration order
};

// Also checks the declarations: formats a pass expects, two writers of one version (a stale
// handle), a read of a version nothing writes, a dependsOn() naming no pass.
[[nodiscard]] Dependencies findDependencies(const Declarations& graph);

// Per pass: whether it runs. Roots are passes with side effects, passes that write an imported
// resource and the writers of sinks; a root keeps alive the producers of what it reads and the
// passes it names in dependsOn(), transitively. A reader that merely has to precede a later
// writer (WAR) is kept only for its own reasons.
[[nodiscard]] std::vector<bool> cullPasses(const Declarations& graph, const Dependencies& deps);

// The passes that run, in an order that respects every dependency among them (Kahn's
// algorithm), ties broken by declaration order so the plan is stable. Throws on a cycle.
[[nodiscard]] std::vector<uint32_t> orderPasses(const Declarations& graph, const Dependencies& deps,
                                                const std::vector<bool>& alive);

// Per resource: the first and last position in `order` that uses it (-1: unused this frame,
// never allocated) and the usage flags a transient is created with.
struct ResourcePlan {
    std::vector<Lifetime> lifetimes;
    std::vector<VkImageUsageFlags> imageUsage;
    std::vector<VkBufferUsageFlags> bufferUsage;
};
[[nodiscard]] ResourcePlan planLifetimes(const Declarations& graph,
                                         std::span<const uint32_t> order);

// The synchronization2 barriers before each pass of `order` and after the last one (imports'
// final accesses, then sinks). Throws when a pass uses one image in two layouts at once or a
// sink names a version nothing writes.
struct BarrierPlan {
    std::vector<std::vector<Barrier>> beforePass; // per position in `order`
    std::vector<Barrier> final;
};
[[nodiscard]] BarrierPlan planBarriers(const Declarations& graph, const Dependencies& deps,
                                       std::span<const uint32_t> order,
                                       std::span<const Lifetime> lifetimes);

} // namespace gt::rg::detail
