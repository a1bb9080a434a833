// The compiled plan of the render graph, inspected without a GPU (Filament's NOOP-backend
// FrameGraph tests): order, culling, barriers and the error cases.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "render_graph/render_graph.hpp"

namespace gt::rg {
namespace {

struct TexData {
    TextureId in, out;
};

auto noop = [](const PassResources&, const TexData&, VkCommandBuffer) {};

ImportedBuffer hostBuffer() {
    return {reinterpret_cast<VkBuffer>(uintptr_t{1}), 64, std::nullopt, Access::HostRead};
}

// A -> B -> readback chain; C writes something nothing reads.
TEST(RenderGraph, OrdersByDependencyAndCullsUnusedPasses) {
    RenderGraph g(64, 32);
    const BufferId host = g.importBuffer("host", hostBuffer());
    TextureId a, b;
    g.addPass<TexData>(
        "a",
        [&](PassBuilder& pb, TexData& d) {
            d.out = a = pb.write(pb.createTexture("a.out", {VK_FORMAT_R32G32B32A32_SFLOAT}),
                                 Access::StorageWrite);
        },
        noop);
    g.addPass<TexData>(
        "c.unused",
        [&](PassBuilder& pb, TexData& d) {
            d.out = pb.write(pb.createTexture("c.out", {}), Access::StorageWrite);
        },
        noop);
    g.addPass<TexData>(
        "b",
        [&](PassBuilder& pb, TexData& d) {
            d.in = pb.read(a, Access::StorageRead);
            d.out = b = pb.write(pb.createTexture("b.out", {}), Access::StorageWrite);
        },
        noop);
    struct RbData {
        TextureId t;
        BufferId host;
    };
    g.addPass<RbData>(
        "readback",
        [&](PassBuilder& pb, RbData& d) {
            d.t = pb.read(b, Access::TransferSrc);
            d.host = pb.write(host, Access::TransferDst);
        },
        [](const PassResources&, const RbData&, VkCommandBuffer) {});
    const CompiledGraph c = g.compile();
    EXPECT_EQ(c.order(), (std::vector<uint32_t>{0, 2, 3}));
    EXPECT_EQ(c.culled, (std::vector<uint32_t>{1}));
    // a.out: written by pass 0, read by pass 1 (position) -> lifetime [0, 1].
    EXPECT_EQ(c.lifetimes[1].firstPass, 0);
    EXPECT_EQ(c.lifetimes[1].lastPass, 1);
    EXPECT_EQ(c.lifetimes[2].firstPass, -1); // c.out never allocated
    EXPECT_TRUE(c.imageUsage[1] & VK_IMAGE_USAGE_STORAGE_BIT);
    EXPECT_TRUE(c.imageUsage[3] & VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
}

TEST(RenderGraph, PlacesReadAfterWriteBarrierWithLayout) {
    RenderGraph g(8, 8);
    const BufferId host = g.importBuffer("host", hostBuffer());
    TextureId t;
    g.addPass<TexData>(
        "write",
        [&](PassBuilder& pb, TexData& d) {
            d.out = t = pb.write(pb.createTexture("t", {}), Access::StorageWrite);
        },
        noop);
    struct RbData {
        TextureId t;
        BufferId host;
    };
    g.addPass<RbData>(
        "copy",
        [&](PassBuilder& pb, RbData& d) {
            d.t = pb.read(t, Access::TransferSrc);
            d.host = pb.write(host, Access::TransferDst);
        },
        [](const PassResources&, const RbData&, VkCommandBuffer) {});
    const CompiledGraph c = g.compile();
    ASSERT_EQ(c.passes.size(), 2u);
    // Before "write": UNDEFINED -> GENERAL, nothing to wait for.
    ASSERT_EQ(c.passes[0].barriers.size(), 1u);
    const Barrier& first = c.passes[0].barriers[0];
    EXPECT_EQ(first.oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
    EXPECT_EQ(first.newLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(first.srcAccess, VK_ACCESS_2_NONE);
    EXPECT_EQ(first.dstStage, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(first.dstAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    // Before "copy": compute write -> transfer read, GENERAL -> TRANSFER_SRC. The host buffer
    // (imported, last used by the host) gets a write-after-host barrier too.
    const Barrier* img = nullptr;
    for (const Barrier& b : c.passes[1].barriers) {
        if (b.image) img = &b;
    }
    ASSERT_NE(img, nullptr);
    EXPECT_EQ(img->srcStage, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(img->srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(img->dstStage,
              VK_PIPELINE_STAGE_2_COPY_BIT | VK_PIPELINE_STAGE_2_BLIT_BIT); // copies and blits
    EXPECT_EQ(img->dstAccess, VK_ACCESS_2_TRANSFER_READ_BIT);
    EXPECT_EQ(img->oldLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(img->newLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    // After the frame the host buffer is made visible to the host.
    ASSERT_EQ(c.finalBarriers.size(), 1u);
    EXPECT_EQ(c.finalBarriers[0].srcAccess, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    EXPECT_EQ(c.finalBarriers[0].dstAccess, VK_ACCESS_2_HOST_READ_BIT);
}

// Two compute dispatches writing the same buffer back to back: the validation layer misses
// this hazard (docs/lavapipe.md), so the plan itself must hold the barrier.
TEST(RenderGraph, PlacesWriteAfterWriteAndWriteAfterReadBarriersOnBuffers) {
    RenderGraph g(8, 8);
    const BufferId host = g.importBuffer("host", hostBuffer());
    struct BufData {
        BufferId in, out;
    };
    auto none = [](const PassResources&, const BufData&, VkCommandBuffer) {};
    BufferId v1, v2, r;
    g.addPass<BufData>(
        "w1",
        [&](PassBuilder& pb, BufData& d) {
            d.out = v1 = pb.write(pb.createBuffer("buf", {256}), Access::StorageWrite);
        },
        none);
    g.addPass<BufData>(
        "reader",
        [&](PassBuilder& pb, BufData& d) {
            d.in = pb.read(v1, Access::StorageRead);
            d.out = r = pb.write(pb.createBuffer("result", {256}), Access::StorageWrite);
        },
        none);
    g.addPass<BufData>(
        "w2",
        [&](PassBuilder& pb, BufData& d) {
            d.in = pb.read(r, Access::StorageRead);
            d.out = v2 = pb.write(v1, Access::StorageWrite);
        },
        none);
    g.addPass<BufData>(
        "copy",
        [&](PassBuilder& pb, BufData& d) {
            d.in = pb.read(v2, Access::TransferSrc);
            d.out = pb.write(host, Access::TransferDst);
        },
        none);
    const CompiledGraph c = g.compile();
    ASSERT_EQ(c.order(), (std::vector<uint32_t>{0, 1, 2, 3}));
    const uint32_t buf = v1.index;
    auto barrierFor = [&](std::size_t pos) -> const Barrier* {
        for (const Barrier& b : c.passes[pos].barriers) {
            if (b.resource == buf) return &b;
        }
        return nullptr;
    };
    // reader: RAW on buf.
    ASSERT_NE(barrierFor(1), nullptr);
    EXPECT_EQ(barrierFor(1)->srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(barrierFor(1)->dstAccess, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    // w2: WAW (w1's write) and WAR (reader) on buf, both compute.
    ASSERT_NE(barrierFor(2), nullptr);
    EXPECT_EQ(barrierFor(2)->srcStage, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    EXPECT_EQ(barrierFor(2)->srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_EQ(barrierFor(2)->dstAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    // copy: compute write -> transfer read.
    ASSERT_NE(barrierFor(3), nullptr);
    EXPECT_EQ(barrierFor(3)->dstStage, VK_PIPELINE_STAGE_2_COPY_BIT | VK_PIPELINE_STAGE_2_BLIT_BIT);
}

TEST(RenderGraph, SecondReaderOfTheSameVersionNeedsNoBarrier) {
    RenderGraph g(8, 8);
    const BufferId host = g.importBuffer("host", hostBuffer());
    struct D {
        TextureId a;
        BufferId b;
    };
    auto none = [](const PassResources&, const D&, VkCommandBuffer) {};
    TextureId t;
    g.addPass<D>(
        "w",
        [&](PassBuilder& pb, D& d) {
            d.a = t = pb.write(pb.createTexture("t", {}), Access::StorageWrite);
        },
        none);
    g.addPass<D>(
        "r1",
        [&](PassBuilder& pb, D& d) {
            d.a = pb.read(t, Access::StorageRead);
            pb.sideEffect();
        },
        none);
    g.addPass<D>(
        "r2",
        [&](PassBuilder& pb, D& d) {
            d.a = pb.read(t, Access::StorageRead);
            d.b = pb.write(host, Access::TransferDst);
        },
        none);
    const CompiledGraph c = g.compile();
    ASSERT_EQ(c.passes.size(), 3u);
    EXPECT_EQ(c.passes[1].barriers.size(), 1u);
    for (const Barrier& b : c.passes[2].barriers)
        EXPECT_NE(b.resource, t.index);
}

TEST(RenderGraph, RejectsReadOfSomethingNothingWrites) {
    RenderGraph g(8, 8);
    g.addPass<TexData>(
        "reader",
        [&](PassBuilder& pb, TexData& d) {
            d.in = pb.read(pb.createTexture("never.written", {}), Access::StorageRead);
            pb.sideEffect();
        },
        noop);
    try {
        (void)g.compile();
        FAIL() << "expected GraphError";
    } catch (const GraphError& e) {
        EXPECT_NE(std::string(e.what()).find("never.written"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("nothing writes"), std::string::npos) << e.what();
    }
}

TEST(RenderGraph, RejectsTwoWritersWithoutOrder) {
    RenderGraph g(8, 8);
    TextureId t0;
    g.addPass<TexData>(
        "make",
        [&](PassBuilder& pb, TexData& d) {
            t0 = pb.createTexture("shared", {});
            d.out = pb.write(t0, Access::StorageWrite);
            pb.sideEffect();
        },
        noop);
    g.addPass<TexData>(
        "stale",
        [&](PassBuilder& pb, TexData& d) {
            d.out = pb.write(t0, Access::StorageWrite); // t0 is stale: "make" wrote it already
            pb.sideEffect();
        },
        noop);
    EXPECT_THROW((void)g.compile(), GraphError);
}

TEST(RenderGraph, RejectsCycle) {
    RenderGraph g(8, 8);
    TextureId t;
    g.addPass<TexData>(
        "a",
        [&](PassBuilder& pb, TexData& d) {
            d.out = t = pb.write(pb.createTexture("t", {}), Access::StorageWrite);
            pb.dependsOn("b");
        },
        noop);
    g.addPass<TexData>(
        "b",
        [&](PassBuilder& pb, TexData& d) {
            d.in = pb.read(t, Access::StorageRead);
            pb.sideEffect();
        },
        noop);
    try {
        (void)g.compile();
        FAIL() << "expected GraphError";
    } catch (const GraphError& e) {
        EXPECT_NE(std::string(e.what()).find("cycle"), std::string::npos) << e.what();
    }
}

TEST(RenderGraph, RejectsMismatchedFormat) {
    RenderGraph g(8, 8);
    TextureId t;
    g.addPass<TexData>(
        "w",
        [&](PassBuilder& pb, TexData& d) {
            d.out = t =
                pb.write(pb.createTexture("ldr", {VK_FORMAT_R8G8B8A8_UNORM}), Access::StorageWrite);
        },
        noop);
    g.addPass<TexData>(
        "r",
        [&](PassBuilder& pb, TexData& d) {
            d.in = pb.read(t, Access::StorageRead, VK_FORMAT_R32G32B32A32_SFLOAT);
            pb.sideEffect();
        },
        noop);
    try {
        (void)g.compile();
        FAIL() << "expected GraphError";
    } catch (const GraphError& e) {
        EXPECT_NE(std::string(e.what()).find("R32G32B32A32_SFLOAT"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("ldr"), std::string::npos);
    }
}

TEST(RenderGraph, RejectsDuplicateNamesAndZeroSize) {
    EXPECT_THROW(RenderGraph(0, 8), GraphError);
    RenderGraph g(8, 8);
    g.addPass<TexData>(
        "p", [](PassBuilder&, TexData&) {}, noop);
    EXPECT_THROW(g.addPass<TexData>(
                     "p", [](PassBuilder&, TexData&) {}, noop),
                 GraphError);
}

TEST(RenderGraph, ImportedHistoryIsReadableWithoutWriterAndTransitionsAtEnd) {
    RenderGraph g(8, 8);
    const TextureId history =
        g.importTexture("history", {reinterpret_cast<VkImage>(uintptr_t{2}), VK_NULL_HANDLE,
                                    VK_FORMAT_R32G32B32A32_SFLOAT, 8, 8, Access::StorageWrite,
                                    Access::StorageRead});
    g.addPass<TexData>(
        "taa",
        [&](PassBuilder& pb, TexData& d) {
            d.in = pb.read(history, Access::SampledCompute);
            d.out = pb.write(history, Access::StorageWrite); // write-after-read in the same graph
        },
        noop);
    // Fails: one pass cannot use one image in two layouts.
    EXPECT_THROW((void)g.compile(), GraphError);

    RenderGraph ok(8, 8);
    const TextureId h2 =
        ok.importTexture("history", {reinterpret_cast<VkImage>(uintptr_t{2}), VK_NULL_HANDLE,
                                     VK_FORMAT_R32G32B32A32_SFLOAT, 8, 8, Access::StorageWrite,
                                     Access::SampledCompute});
    TextureId cur;
    ok.addPass<TexData>(
        "resolve",
        [&](PassBuilder& pb, TexData& d) {
            d.in = pb.read(h2, Access::StorageRead);
            d.out = cur = pb.write(pb.createTexture("current", {VK_FORMAT_R32G32B32A32_SFLOAT}),
                                   Access::StorageWrite);
        },
        noop);
    ok.addPass<TexData>(
        "store",
        [&](PassBuilder& pb, TexData& d) {
            d.in = pb.read(cur, Access::StorageRead);
            d.out = pb.write(h2, Access::StorageWrite);
        },
        noop);
    const CompiledGraph c = ok.compile();
    EXPECT_EQ(c.order(), (std::vector<uint32_t>{0, 1}));
    ASSERT_EQ(c.finalBarriers.size(), 1u);
    EXPECT_EQ(c.finalBarriers[0].newLayout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    // "store" overwrites what "resolve" read: a write-after-read barrier on the history.
    bool war = false;
    for (const Barrier& b : c.passes[1].barriers) {
        war |= b.resource == h2.index && (b.srcStage & VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
    }
    EXPECT_TRUE(war);
}

TEST(RenderGraph, WritesGraphviz) {
    RenderGraph g(8, 8);
    g.addPass<TexData>(
        "only",
        [&](PassBuilder& pb, TexData& d) {
            d.out = pb.write(pb.createTexture("img", {}), Access::StorageWrite);
            pb.sideEffect();
        },
        noop);
    const std::string dot = g.toDot(g.compile());
    EXPECT_NE(dot.find("digraph"), std::string::npos);
    EXPECT_NE(dot.find("only"), std::string::npos);
    EXPECT_NE(dot.find("img v1"), std::string::npos);
}

} // namespace
} // namespace gt::rg

namespace gt::rg {
namespace {

// Two views of one frame add the same passes under their own scopes: names do not clash, each
// chain is ordered and kept, and dependsOn() finds the pass of its own view.
TEST(RenderGraphScopes, SamePassTwiceUnderTwoScopes) {
    RenderGraph g(64, 32);
    std::vector<TextureId> outs;
    for (const char* eye : {"left", "right"}) {
        const RenderGraph::Scope scope = g.scope(eye, 16, 8);
        EXPECT_EQ(g.outputWidth(), 16u);
        EXPECT_EQ(g.outputHeight(), 8u);
        TextureId traced;
        g.addPass<TexData>(
            "trace",
            [&](PassBuilder& pb, TexData& d) {
                d.out = traced = pb.write(pb.createTexture("radiance", {}), Access::StorageWrite);
            },
            noop);
        g.addPass<TexData>(
            "tonemap",
            [&](PassBuilder& pb, TexData& d) {
                d.in = pb.read(traced, Access::StorageRead);
                d.out = pb.write(pb.createTexture("ldr", {}), Access::StorageWrite);
                pb.dependsOn("trace");
                outs.push_back(d.out);
            },
            noop);
    }
    EXPECT_EQ(g.outputWidth(), 64u); // the scope's size ends with it
    for (const TextureId t : outs) {
        g.sink(t, Access::StorageRead);
    }
    const CompiledGraph c = g.compile();
    ASSERT_EQ(c.passes.size(), 4u);
    EXPECT_TRUE(c.culled.empty());
    std::vector<std::string> names;
    for (const uint32_t p : c.order()) {
        names.push_back(g.passName(p));
    }
    EXPECT_EQ(names, (std::vector<std::string>{"left.trace", "left.tonemap", "right.trace",
                                               "right.tonemap"}));
    EXPECT_EQ(g.resourceName(outs[1].index), "right.ldr");
    // Nested scopes join their prefixes.
    {
        const RenderGraph::Scope outer = g.scope("hmd");
        const RenderGraph::Scope inner = g.scope("left");
        EXPECT_EQ(g.scopedName("taa"), "hmd.left.taa");
    }
    EXPECT_EQ(g.scopedName("taa"), "taa");
    // Within one scope the name is still unique.
    const RenderGraph::Scope again = g.scope("left");
    EXPECT_THROW(g.addPass<TexData>(
                     "trace", [](PassBuilder&, TexData&) {}, noop),
                 GraphError);
}

// A sink keeps its producer alive (no empty pass needed) and leaves the resource in the access
// it names, as a final barrier; a version nothing writes cannot be a sink.
TEST(RenderGraphSinks, SinkKeepsProducerAndTransitionsAtEnd) {
    RenderGraph g(8, 8);
    TextureId out;
    g.addPass<TexData>(
        "produce",
        [&](PassBuilder& pb, TexData& d) {
            d.out = out = pb.write(pb.createTexture("img", {}), Access::StorageWrite);
        },
        noop);
    g.addPass<TexData>(
        "unused",
        [&](PassBuilder& pb, TexData& d) {
            d.out = pb.write(pb.createTexture("other", {}), Access::StorageWrite);
        },
        noop);
    {
        const CompiledGraph without = g.compile();
        EXPECT_TRUE(without.passes.empty()); // nothing is a result yet: all culled
    }
    g.sink(out, Access::TransferSrc);
    const CompiledGraph c = g.compile();
    ASSERT_EQ(c.order(), (std::vector<uint32_t>{0}));
    ASSERT_EQ(c.finalBarriers.size(), 1u);
    EXPECT_EQ(c.finalBarriers[0].oldLayout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(c.finalBarriers[0].newLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    EXPECT_EQ(c.finalBarriers[0].srcAccess, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    EXPECT_NE(c.imageUsage[out.index] & VK_IMAGE_USAGE_TRANSFER_SRC_BIT, 0u);

    RenderGraph bad(8, 8);
    TextureId created;
    bad.addPass<TexData>(
        "declare",
        [&](PassBuilder& pb, TexData& d) { d.out = created = pb.createTexture("t", {}); }, noop);
    bad.sink(created, Access::StorageRead);
    EXPECT_THROW((void)bad.compile(), GraphError);
}

// An imported array layer is the subresource every barrier names.
TEST(RenderGraphImports, BarriersNameTheImportedLayer) {
    RenderGraph g(8, 8);
    const TextureId swap = g.importTexture(
        "xr.swapchain",
        {reinterpret_cast<VkImage>(uintptr_t{2}), reinterpret_cast<VkImageView>(uintptr_t{3}),
         VK_FORMAT_R8G8B8A8_UNORM, 8, 8, std::nullopt, Access::StorageRead, 1});
    g.addPass<TexData>(
        "write", [&](PassBuilder& pb, TexData& d) { d.out = pb.write(swap, Access::StorageWrite); },
        noop);
    const CompiledGraph c = g.compile();
    ASSERT_EQ(c.passes.size(), 1u);
    ASSERT_EQ(c.passes[0].barriers.size(), 1u);
    EXPECT_EQ(c.passes[0].barriers[0].layer, 1u);
    EXPECT_EQ(c.passes[0].barriers[0].newLayout, VK_IMAGE_LAYOUT_GENERAL);
}

// Retired objects live until every frame that may use them has finished.
TEST(DeferredRelease, KeepsObjectsUntilTheirFrameFinished) {
    DeferredRelease r;
    auto a = std::make_shared<int>(1);
    auto b = std::make_shared<int>(2);
    std::weak_ptr<int> wa = a, wb = b;
    r.retire(std::move(a), 3);
    r.retire(std::move(b), 5);
    r.collect(2);
    EXPECT_FALSE(wa.expired());
    r.collect(3);
    EXPECT_TRUE(wa.expired());
    EXPECT_FALSE(wb.expired());
    r.collect(10);
    EXPECT_TRUE(wb.expired());
    EXPECT_EQ(r.pending(), 0u);
}

} // namespace
} // namespace gt::rg
