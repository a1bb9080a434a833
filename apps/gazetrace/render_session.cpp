#include "render_session.hpp"

#include <chrono>
#include <cstdlib>
#include <functional>
#include <set>
#include <tuple>

#include "core/error.hpp"
#include "core/log.hpp"
#include "foveation/gpu_point_set.hpp"
#include "foveation/neighbour_index.hpp"
#include "foveation/point_set_cache.hpp"
#include "point_sample/point_sample.hpp"
#include "rbf_solve/rbf_solve.hpp"
#include "readback/readback.hpp"
#include "reference/reference.hpp"
#include "scene/bvh.hpp"
#include "scene/gltf_loader.hpp"
#include "taa/taa.hpp"
#include "tonemap/tonemap.hpp"
#include "trace/gpu_scene.hpp"
#include "vk/context.hpp"
#include "vk/resources.hpp"

namespace gt::app {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}
} // namespace

struct RenderSession::Impl {
    scene::Scene scene;
    std::optional<scene::Bvh> bvh;
    std::unique_ptr<vk::Context> ctx;
    std::optional<trace::GpuScene> gpuScene;
    std::optional<passes::ReferencePass> reference;
    std::optional<passes::TonemapPass> tonemap;
    std::optional<foveation::PointSet> points;
    std::optional<foveation::NeighbourIndex> neighbours;
    std::optional<foveation::GpuPointSet> gpuPoints;
    std::optional<passes::PointSamplePass> pointSample;
    std::optional<passes::InterpolatePass> interpolate;
    std::optional<passes::RbfSolvePass> rbfSolve;
    std::optional<foveation::GpuRbfInverse> rbfInverse; // for the last RBF settings used
    Prepared rbfPrepared;
    std::optional<foveation::GpuPixelKnnTable> knnTable; // for the last k asked of it
    Prepared knnTablePrepared;
    std::optional<foveation::GpuRbfPixelWeights> rbfPixelWeights; // RBF with the table

    // The thesis's per-pixel table, and for RBF its per-pixel weights, when the settings ask
    // for them: built on the CPU once per k (and RBF kernel and shape).
    passes::InterpolateInputs tableInputs(const passes::InterpolateSettings& s) {
        if (!passes::usesPixelTable(s)) {
            // Hundreds of MB: give them back to whatever runs next.
            knnTable.reset();
            rbfPixelWeights.reset();
            return {};
        }
        std::optional<foveation::PixelKnnTable> table;
        if (!knnTable || knnTable->k() != s.k) {
            knnTable.reset();
            rbfPixelWeights.reset();
            table.emplace(*points, *neighbours, s.k);
            knnTable.emplace(*ctx, *table);
            knnTablePrepared = {table->buildSeconds() * 1e3,
                                static_cast<double>(table->bytes()) / 1e6};
        }
        if (s.method != passes::Interpolation::Rbf) {
            rbfPixelWeights.reset();
            return {std::nullopt, &*knnTable, nullptr};
        }
        if (!rbfPixelWeights || rbfPixelWeights->kernel() != s.kernel ||
            rbfPixelWeights->shape() != s.rbfShape) {
            rbfPixelWeights.reset();
            if (!table) {
                table.emplace(*points, *neighbours, s.k); // same k, another kernel or shape
            }
            const foveation::RbfPixelWeights weights(*points, *table, s.kernel, s.rbfShape);
            rbfPixelWeights.emplace(*ctx, weights);
            rbfPrepared = {weights.buildSeconds() * 1e3,
                           static_cast<double>(weights.bytes()) / 1e6};
        }
        return {std::nullopt, &*knnTable, &*rbfPixelWeights};
    }

    const foveation::GpuRbfInverse& inverseFor(const passes::InterpolateSettings& s) {
        if (!rbfInverse || rbfInverse->k() != s.k || rbfInverse->kernel() != s.kernel ||
            rbfInverse->shape() != s.rbfShape) {
            rbfInverse.reset();
            const foveation::RbfInverse inv =
                foveation::buildRbfInverse(*points, *neighbours, s.k, s.kernel, s.rbfShape);
            rbfInverse.emplace(*ctx, inv);
            rbfPrepared = {inv.seconds * 1e3,
                           static_cast<double>(inv.inverse.size() * sizeof(float)) / 1e6};
        }
        return *rbfInverse;
    }
    std::optional<passes::TaaPass> taa;
    std::optional<passes::TaaHistory> taaHistory;
    std::optional<rg::TransientPool> pool;
    bool warmReference = false;
    // The foveated pipeline variants (interpolation method, reads the table, point_sample lanes
    // per point) that have run once: each is its own specialised pipeline, compiled by lavapipe
    // at its first dispatch.
    std::set<std::tuple<passes::Interpolation, bool, uint32_t>> warmFoveated;

    using AddRadiance = std::function<rg::TextureId(rg::RenderGraph&)>;

    FrameResult run(const AddRadiance& add, uint32_t w, uint32_t h, bool pixels, bool dot,
                    rg::TransientPool& p) {
        const auto t = Clock::now();
        std::optional<vk::Buffer> host;
        rg::RenderGraph graph(w, h);
        const rg::TextureId ldr = tonemap->add(graph, add(graph), scene.exposure);
        if (pixels) {
            host.emplace(*ctx, vk::BufferDesc{static_cast<VkDeviceSize>(w) * h * 4,
                                              VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                              vk::MemoryUsage::Readback, "readback.frame"});
            const rg::BufferId hostId = graph.importBuffer(
                "frame.host", {host->handle(), host->size(), std::nullopt, rg::Access::HostRead});
            passes::addReadbackPass(graph, "frame", ldr, hostId);
        } else {
            // Without a readback nothing would consume the image: keep the tone mapper alive.
            struct Keep {
                rg::TextureId t;
            };
            graph.addPass<Keep>(
                "frame.end",
                [&](rg::PassBuilder& b, Keep& k) {
                    k.t = b.read(ldr, rg::Access::StorageRead);
                    b.sideEffect();
                },
                [](const rg::PassResources&, const Keep&, VkCommandBuffer) {});
        }
        const rg::CompiledGraph compiled = graph.compile();
        FrameResult f;
        if (dot) {
            f.dot = graph.toDot(compiled);
        }
        f.timings = graph.execute(compiled, p);
        if (pixels) {
            f.pixels.resize(host->size());
            host->download(std::as_writable_bytes(std::span(f.pixels)));
        }
        f.wallMs = msSince(t);
        return f;
    }
};

RenderSession::RenderSession(const std::string& sceneSpec, bool validate)
    : mImpl(std::make_unique<Impl>()) {
    const auto t0 = Clock::now();
    scene::GltfLoadReport report;
    mImpl->scene = scene::loadScene(sceneSpec, &report);
    for (const std::string& w : report.warnings) {
        log::warn(sceneSpec + ": " + w);
    }
    mLoadMs = msSince(t0);
    const auto t1 = Clock::now();
    mImpl->bvh.emplace(mImpl->scene);
    mBvhMs = msSince(t1);
    const char* env = std::getenv("GAZETRACE_DEVICE");
    mImpl->ctx =
        std::make_unique<vk::Context>(vk::ContextOptions{.validation = validate,
                                                         .synchronizationValidation = validate,
                                                         .deviceOverride = env ? env : ""});
    mImpl->gpuScene.emplace(*mImpl->ctx, mImpl->scene, *mImpl->bvh);
    mImpl->reference.emplace(*mImpl->ctx);
    mImpl->tonemap.emplace(*mImpl->ctx);
    mImpl->pool.emplace(*mImpl->ctx);
}

RenderSession::~RenderSession() = default;

vk::Context& RenderSession::context() {
    return *mImpl->ctx;
}
const scene::Scene& RenderSession::scene() const {
    return mImpl->scene;
}

void RenderSession::setCamera(const scene::Camera& camera) {
    mImpl->scene.camera = camera;
}

const scene::BvhBuildStats& RenderSession::bvhStats() const {
    return mImpl->bvh->stats();
}

void RenderSession::preparePointSet(const foveation::PointSetParams& params,
                                    const std::filesystem::path& cacheDir) {
    const auto t = Clock::now();
    foveation::CachedPointSet c = foveation::loadOrGenerate(cacheDir, params);
    if (!c.warning.empty()) {
        log::warn(c.warning);
    }
    mPointSetMs = msSince(t);
    mImpl->rbfInverse.reset();
    mImpl->knnTable.reset();
    mImpl->rbfPixelWeights.reset();
    mImpl->gpuPoints.reset();
    mImpl->neighbours.reset();
    mImpl->points.emplace(std::move(c.set));
    mImpl->neighbours.emplace(*mImpl->points, foveation::NeighbourIndex::kMaxNeighbours);
    mNeighbourMs = mImpl->neighbours->buildSeconds() * 1e3;
    mNeighbourMb = static_cast<double>(mImpl->neighbours->bytes()) / 1e6;
    mImpl->gpuPoints.emplace(*mImpl->ctx, *mImpl->points, *mImpl->neighbours);
    if (!mImpl->pointSample) {
        mImpl->pointSample.emplace(*mImpl->ctx);
    }
    if (!mImpl->interpolate) {
        mImpl->interpolate.emplace(*mImpl->ctx);
    }
    if (!mImpl->rbfSolve) {
        mImpl->rbfSolve.emplace(*mImpl->ctx);
    }
    if (!mImpl->taa) {
        mImpl->taa.emplace(*mImpl->ctx);
    }
    mImpl->taaHistory.emplace(*mImpl->ctx, params.display.width, params.display.height);
}

const foveation::PointSet& RenderSession::pointSet() const {
    if (!mImpl->points) {
        throw Error("no point set prepared");
    }
    return *mImpl->points;
}

std::size_t RenderSession::pointsSampled(glm::vec2 gaze) const {
    const foveation::PointSet& set = pointSet();
    const auto w = set.params().display.width, h = set.params().display.height;
    const glm::vec2 off = passes::gazeOffset(gaze, w, h);
    return set.countOnScreen(off.x + static_cast<float>(w), off.y + static_cast<float>(h),
                             passes::kSampleMargin);
}

FrameResult RenderSession::reference(uint32_t w, uint32_t h, uint32_t spp, uint32_t seed,
                                     bool pixels, bool dot) {
    Impl& m = *mImpl;
    auto add = [&](rg::RenderGraph& g) {
        return m.reference->add(g, *m.gpuScene, m.scene.camera, {spp, seed});
    };
    if (!m.warmReference) {
        rg::TransientPool warm(*m.ctx);
        auto tiny = [&](rg::RenderGraph& g) {
            return m.reference->add(g, *m.gpuScene, m.scene.camera, {1, 0});
        };
        (void)m.run(tiny, 16, 16, true, false, warm);
        m.warmReference = true;
    }
    return m.run(add, w, h, pixels, dot, *m.pool);
}

Prepared RenderSession::rbfPrepared() const {
    return mImpl->rbfPrepared;
}

Prepared RenderSession::knnTablePrepared() const {
    return mImpl->knnTablePrepared;
}

FrameResult RenderSession::foveated(const FoveatedSettings& s, bool pixels, bool dot) {
    Impl& m = *mImpl;
    if (!m.gpuPoints) {
        throw Error("no point set prepared");
    }
    const uint32_t w = m.points->params().display.width, h = m.points->params().display.height;
    const passes::InterpolateInputs prepared = m.tableInputs(s.interpolation);
    const bool solve = passes::usesRbfSolve(s.interpolation);
    // point_sample -> (rbf_solve) -> interpolate, with `rays` per point traced by `lanes`
    // threads each.
    const uint32_t lanes = passes::pointSampleLanes(*m.ctx, s.raysPerPoint);
    auto addImage = [&](rg::RenderGraph& g, uint32_t rays) {
        const rg::BufferId samples =
            m.pointSample->add(g, *m.gpuScene, m.scene.camera, *m.gpuPoints, s.gaze, rays, lanes);
        passes::InterpolateInputs in = prepared;
        if (solve) {
            in.lambdas = m.rbfSolve->add(g, *m.gpuPoints, m.inverseFor(s.interpolation), samples,
                                         s.gaze, s.interpolation);
        }
        return m.interpolate->add(g, *m.gpuPoints, samples, s.gaze, s.interpolation, in);
    };
    auto add = [&](rg::RenderGraph& g) {
        const rg::TextureId image = addImage(g, s.raysPerPoint);
        if (!s.taa) {
            return image;
        }
        return m.taa->add(g, *m.taaHistory, image, m.scene.camera, s.gaze, s.saccade);
    };
    const auto variant =
        std::make_tuple(s.interpolation.method, passes::usesPixelTable(s.interpolation), lanes);
    if (!m.warmFoveated.contains(variant)) {
        // One untimed frame, full size, one ray per point, through every pipeline this frame
        // uses (lavapipe compiles at first dispatch) and without touching the TAA history.
        // The lanes stay those of the timed frame: idle lanes cost little and trace nothing.
        rg::TransientPool warm(*m.ctx);
        (void)m.run([&](rg::RenderGraph& g) { return addImage(g, 1); }, w, h, true, false, warm);
        m.warmFoveated.insert(variant);
    }
    return m.run(add, w, h, pixels, dot, *m.pool);
}

} // namespace gt::app
