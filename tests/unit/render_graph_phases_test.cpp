// The phases of RenderGraph::compile one at a time, on declarations built by hand: each phase
// can be wrong on its own (a cull that drops a sink's producer, a missing read-after-write
// barrier) and is checked here without the others in the way.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "render_graph/compile_phases.hpp"

namespace gt::rg::detail {
namespace {

// Declarations as the builder records them: versions are explicit, a write names the version
// it produces.
struct Graph {
    std::vector<Resource> resources;
    std::vector<Pass> passes;
    std::vector<Sink> sinks;

    uint32_t texture(std::string name) {
        Resource r;
        r.name = std::move(name);
        r.image = true;
        resources.push_back(r);
        return static_cast<uint32_t>(resources.size() - 1);
    }
    uint32_t importedBuffer(std::string name, std::optional<Access> finalAccess) {
        Resource r;
        r.name = std::move(name);
        r.imported = true;
        r.importedBuffer.finalAccess = finalAccess;
        resources.push_back(r);
        return static_cast<uint32_t>(resources.size() - 1);
    }
    uint32_t pass(std::string name) {
        passes.push_back(Pass{std::move(name), {}, {}, false, {}});
        return static_cast<uint32_t>(passes.size() - 1);
    }
    void read(uint32_t p, uint32_t r, uint32_t version, Access a) {
        passes[p].uses.push_back({r, version, a, false, VK_FORMAT_UNDEFINED});
    }
    void write(uint32_t p, uint32_t r, uint32_t newVersion, Access a) {
        passes[p].uses.push_back({r, newVersion, a, true, VK_FORMAT_UNDEFINED});
    }
    [[nodiscard]] Declarations view() const { return {passes, resources, sinks}; }
};

TEST(RenderGraphDependencies, ReaderAfterWriterAndNextWriterAfterReaders) {
    Graph g;
    const uint32_t t = g.texture("t");
    const uint32_t w1 = g.pass("w1"), reader = g.pass("reader"), w2 = g.pass("w2");
    const uint32_t late = g.pass("late");
    g.write(w1, t, 1, Access::StorageWrite);
    g.read(reader, t, 1, Access::StorageRead);
    g.write(w2, t, 2, Access::StorageWrite);
    g.passes[late].after.push_back("reader");
    const Dependencies d = findDependencies(g.view());
    EXPECT_EQ(d.writer.at({t, 1}), w1);
    EXPECT_EQ(d.writer.at({t, 2}), w2);
    EXPECT_EQ(d.preds[w1], (std::set<uint32_t>{}));
    EXPECT_EQ(d.preds[reader], (std::set<uint32_t>{w1}));     // read after write
    EXPECT_EQ(d.preds[w2], (std::set<uint32_t>{w1, reader})); // WAW and WAR
    EXPECT_EQ(d.preds[late], (std::set<uint32_t>{reader}));   // dependsOn
}

TEST(RenderGraphDependencies, RejectsTwoWritersOfOneVersionAndUnknownPasses) {
    Graph g;
    const uint32_t t = g.texture("t");
    const uint32_t a = g.pass("a"), b = g.pass("b");
    g.write(a, t, 1, Access::StorageWrite);
    g.write(b, t, 1, Access::StorageWrite); // through a stale handle
    EXPECT_THROW((void)findDependencies(g.view()), GraphError);
    g.passes[b].uses.clear();
    g.passes[b].after.push_back("nowhere");
    EXPECT_THROW((void)findDependencies(g.view()), GraphError);
}

// producer -> consumer -> sink; `unread` writes what nothing reads.
TEST(RenderGraphCull, KeepsProducersOfASinkAndDropsAPassNothingReads) {
    Graph g;
    const uint32_t a = g.texture("a"), b = g.texture("b"), c = g.texture("c");
    const uint32_t producer = g.pass("producer"), unread = g.pass("unread");
    const uint32_t consumer = g.pass("consumer");
    g.write(producer, a, 1, Access::StorageWrite);
    g.write(unread, c, 1, Access::StorageWrite);
    g.read(consumer, a, 1, Access::StorageRead);
    g.write(consumer, b, 1, Access::StorageWrite);
    EXPECT_EQ(cullPasses(g.view(), findDependencies(g.view())),
              (std::vector<bool>{false, false, false})); // no result: nothing runs
    g.sinks.push_back({b, 1, Access::StorageRead});
    EXPECT_EQ(cullPasses(g.view(), findDependencies(g.view())),
              (std::vector<bool>{true, false, true}));
}

// `reader` must precede `overwrite` (WAR), but what it writes is never used: it is culled, while
// the pass that wrote the version `overwrite` builds on stays.
TEST(RenderGraphCull, AReaderThatOnlyPrecedesALaterWriterIsDropped) {
    Graph g;
    const uint32_t t = g.texture("t"), scratch = g.texture("scratch");
    const uint32_t host = g.importedBuffer("host", Access::HostRead);
    const uint32_t first = g.pass("first"), reader = g.pass("reader");
    const uint32_t overwrite = g.pass("overwrite"), copy = g.pass("copy");
    g.write(first, t, 1, Access::StorageWrite);
    g.read(reader, t, 1, Access::StorageRead);
    g.write(reader, scratch, 1, Access::StorageWrite);
    g.write(overwrite, t, 2, Access::StorageWrite);
    g.read(copy, t, 2, Access::TransferSrc);
    g.write(copy, host, 1, Access::TransferDst); // an import: a root
    EXPECT_EQ(cullPasses(g.view(), findDependencies(g.view())),
              (std::vector<bool>{true, false, true, true}));
    g.passes[reader].sideEffect = true; // kept for its own reasons
    EXPECT_EQ(cullPasses(g.view(), findDependencies(g.view())),
              (std::vector<bool>{true, true, true, true}));
}

TEST(RenderGraphOrder, FollowsDependenciesAndBreaksTiesByDeclaration) {
    Graph g;
    for (const char* name : {"p0", "p1", "p2", "p3"})
        (void)g.pass(name);
    Dependencies d;
    d.preds = {{2}, {}, {}, {0}}; // p2 before p0 before p3
    EXPECT_EQ(orderPasses(g.view(), d, {true, true, true, true}),
              (std::vector<uint32_t>{1, 2, 0, 3}));
    // A culled pass is neither placed nor waited for.
    EXPECT_EQ(orderPasses(g.view(), d, {true, true, false, true}),
              (std::vector<uint32_t>{0, 1, 3}));
}

TEST(RenderGraphOrder, RejectsACycleNamingItsPasses) {
    Graph g;
    for (const char* name : {"free", "ping", "pong"})
        (void)g.pass(name);
    Dependencies d;
    d.preds = {{}, {2}, {1}};
    try {
        (void)orderPasses(g.view(), d, {true, true, true});
        FAIL() << "a cycle compiled";
    } catch (const GraphError& e) {
        EXPECT_NE(std::string(e.what()).find("'ping', 'pong'"), std::string::npos) << e.what();
    }
}

TEST(RenderGraphLifetimes, SpanFirstToLastUseInExecutionOrder) {
    Graph g;
    const uint32_t a = g.texture("a"), b = g.texture("b"), unused = g.texture("unused");
    const uint32_t host = g.importedBuffer("host", Access::HostRead);
    const uint32_t p0 = g.pass("p0"), p1 = g.pass("p1"), p2 = g.pass("p2");
    g.write(p0, a, 1, Access::StorageWrite);
    g.read(p1, a, 1, Access::SampledCompute);
    g.write(p1, b, 1, Access::StorageWrite);
    g.read(p2, b, 1, Access::TransferSrc);
    g.write(p2, host, 1, Access::TransferDst);
    const std::vector<uint32_t> order{p0, p1, p2};
    const ResourcePlan plan = planLifetimes(g.view(), order);
    EXPECT_EQ(plan.lifetimes[a].firstPass, 0);
    EXPECT_EQ(plan.lifetimes[a].lastPass, 1);
    EXPECT_EQ(plan.lifetimes[b].firstPass, 1);
    EXPECT_EQ(plan.lifetimes[b].lastPass, 2);
    EXPECT_EQ(plan.lifetimes[unused].firstPass, -1); // never allocated
    EXPECT_EQ(plan.imageUsage[a], VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT);
    EXPECT_EQ(plan.imageUsage[b], VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
    EXPECT_EQ(plan.imageUsage[unused], 0u);
}

const Barrier* barrierFor(const std::vector<Barrier>& list, uint32_t resource) {
    for (const Barrier& b : list) {
        if (b.resource == resource) return &b;
    }
    return nullptr;
}

// write -> read -> second read of the same version -> host copy.
TEST(RenderGraphBarriers, OneBarrierBetweenAWriteAndItsFirstRead) {
    Graph g;
    const uint32_t t = g.texture("t");
    const uint32_t host = g.importedBuffer("host", Access::HostRead);
    const uint32_t writer = g.pass("writer"), r1 = g.pass("r1"), r2 = g.pass("r2");
    g.write(writer, t, 1, Access::StorageWrite);
    g.read(r1, t, 1, Access::SampledCompute);
    g.read(r2, t, 1, Access::SampledCompute);
    g.write(r2, host, 1, Access::TransferDst);
    const std::vector<uint32_t> order{writer, r1, r2};
    const ResourcePlan lifetimes = planLifetimes(g.view(), order);
    const BarrierPlan plan =
        planBarriers(g.view(), findDependencies(g.view()), order, lifetimes.lifetimes);
    ASSERT_EQ(plan.beforePass.size(), 3u);
    // Before the write: only the transition out of UNDEFINED, nothing to wait for.
    const Barrier* first = barrierFor(plan.beforePass[0], t);
    ASSERT_NE(first, nullptr);
    EXPECT_EQ(first->srcStage, VK_PIPELINE_STAGE_2_NONE);
    EXPECT_EQ(first->oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    EXPECT_EQ(first->newLayout, VK_IMAGE_LAYOUT_GENERAL);
    // Before the first read: wait for the storage write, make it visible to sampling.
    const Barrier* raw = barrierFor(plan.beforePass[1], t);
    ASSERT_NE(raw, nullptr);
    EXPECT_EQ(raw->srcStage, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(raw->srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(raw->dstStage, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(raw->dstAccess, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    EXPECT_EQ(raw->oldLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(raw->newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    // The second reader finds the write already visible.
    EXPECT_EQ(barrierFor(plan.beforePass[2], t), nullptr);
    // After the frame the host buffer is handed to the host.
    const Barrier* fin = barrierFor(plan.final, host);
    ASSERT_NE(fin, nullptr);
    EXPECT_EQ(fin->srcAccess, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    EXPECT_EQ(fin->dstAccess, VK_ACCESS_2_HOST_READ_BIT);
}

TEST(RenderGraphBarriers, RejectsOneImageInTwoLayoutsInOnePassAndSinksOfUnwrittenVersions) {
    Graph g;
    const uint32_t t = g.texture("t");
    const uint32_t writer = g.pass("writer"), both = g.pass("both");
    g.write(writer, t, 1, Access::StorageWrite);
    g.read(both, t, 1, Access::SampledCompute);
    g.read(both, t, 1, Access::StorageRead);
    const std::vector<uint32_t> order{writer, both};
    const ResourcePlan lifetimes = planLifetimes(g.view(), order);
    EXPECT_THROW(
        (void)planBarriers(g.view(), findDependencies(g.view()), order, lifetimes.lifetimes),
        GraphError);
    g.passes[both].uses.pop_back();
    g.sinks.push_back({t, 5, Access::StorageRead});
    EXPECT_THROW(
        (void)planBarriers(g.view(), findDependencies(g.view()), order, lifetimes.lifetimes),
        GraphError);
    g.sinks.back().version = 1;
    EXPECT_NO_THROW(
        (void)planBarriers(g.view(), findDependencies(g.view()), order, lifetimes.lifetimes));
}

} // namespace
} // namespace gt::rg::detail
