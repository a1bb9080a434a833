#include "renderer.hpp"

#include <algorithm>
#include <chrono>

#include "core/error.hpp"
#include "core/log.hpp"
#include "denoise/denoise.hpp"
#include "lens/lens.hpp"
#include "scene/gltf_loader.hpp"
#include "scene/subdivision.hpp"
#include "taa/taa.hpp"
#include "tonemap/tonemap.hpp"
#include "trace/gpu_scene.hpp"
#include "vk/context.hpp"

namespace gt::render {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}
constexpr const char* kTaaHistory = "taa";
constexpr const char* kTaaWeightHistory = "taa.weight";
constexpr const char* kTaaSignatureHistory = "taa.signature"; // a scene that moves

using CoarserLevels = std::vector<std::pair<scene::Scene, scene::Bvh>>;

// The scene `spec` at full detail, and its coarser geometric LOD levels into `coarser`.
scene::Scene loadLevels(const std::string& spec, const scene::GltfLoadOptions& load,
                        CoarserLevels& coarser) {
    scene::GltfLoadReport report;
    scene::Scene full = scene::loadScene(spec, &report, load);
    for (const std::string& w : report.warnings) {
        log::warn(spec + ": " + w);
    }
    if (!full.cages.empty()) {
        // Geometric LOD (Guenter et al. 2012, 6): the cages refined once per level, a BVH per
        // level; the coarser levels hold geometry only, the full scene is refined in place last.
        for (std::size_t l = 1; l < scene::kLodRefinements.size(); ++l) {
            scene::Scene level = scene::refinedGeometry(full, scene::kLodRefinements[l]);
            scene::Bvh bvh(level);
            coarser.emplace_back(std::move(level), std::move(bvh));
        }
        scene::refineCages(full, scene::kLodRefinements[0]);
    }
    return full;
}

// `dynamic`: the scene's two-level part (null where nothing moves), whose tables get one copy
// per frame in flight (`copies`).
std::unique_ptr<trace::GpuScene> uploadLevels(vk::Context& ctx, const scene::Scene& full,
                                              const scene::Bvh& bvh, const CoarserLevels& coarser,
                                              const scene::DynamicGeometry* dynamic = nullptr,
                                              uint32_t copies = 1) {
    std::vector<trace::LodGeometry> levels{{&full, &bvh}};
    for (const auto& [level, levelBvh] : coarser)
        levels.push_back({&level, &levelBvh});
    if (dynamic != nullptr) return std::make_unique<trace::GpuScene>(ctx, levels, *dynamic, copies);
    return std::make_unique<trace::GpuScene>(ctx, levels);
}

// The two-level part of a scene with a rig, posed at `seconds` without motion; null for a scene
// where nothing moves. An animation the rig lacks fails naming it (scene::chooseAnimation).
std::unique_ptr<scene::DynamicGeometry> makeDynamic(const scene::Scene& s,
                                                    const std::string& animation, double seconds) {
    if (!s.animated()) return nullptr;
    return std::make_unique<scene::DynamicGeometry>(
        s.rig, scene::chooseAnimation(*s.rig, animation), seconds);
}
} // namespace

// A scene added after the first: what the constructor keeps of scene 0, on the same device.
struct Renderer::LoadedScene {
    scene::Scene scene;
    CoarserLevels coarser;
    std::optional<scene::Bvh> bvh;
    std::unique_ptr<scene::DynamicGeometry> dynamic;
    std::unique_ptr<trace::GpuScene> gpu;
};

Renderer::Renderer(const RendererOptions& o) {
    const auto t0 = Clock::now();
    mScene = loadLevels(o.scene, o.sceneLoad, mCoarser);
    mLoadMs = msSince(t0);
    const auto t1 = Clock::now();
    mBvh.emplace(mScene);
    mBvhMs = msSince(t1);
    vk::ContextOptions co = o.display;
    co.validation = o.validate;
    co.synchronizationValidation = o.validate;
    co.deviceOverride = o.deviceOverride;
    mAnimation = o.animation;
    mDynamic = makeDynamic(mScene, mAnimation, mSceneTime);
    mCtx = std::make_unique<vk::Context>(co);
    const bool cpuDevice = mCtx->properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    mRing = std::make_unique<rg::FrameRing>(*mCtx, o.framesInFlight != 0 ? o.framesInFlight
                                                                         : (cpuDevice ? 1u : 2u));
    mGpuScene =
        uploadLevels(*mCtx, mScene, *mBvh, mCoarser, mDynamic.get(), mRing->framesInFlight());
    mTaa = std::make_unique<passes::TaaPass>(*mCtx);
    mTonemap = std::make_unique<passes::TonemapPass>(*mCtx);
    mDenoise = std::make_unique<passes::DenoisePass>(*mCtx);
    mLens = std::make_unique<passes::LensPass>(*mCtx);
    mHistory = std::make_unique<rg::HistoryPool>(*mCtx, &mRing->deferredRelease());
}

Renderer::~Renderer() {
    if (mRing) {
        try {
            mRing->waitIdle();
        } catch (const std::exception&) { // NOLINT(bugprone-empty-catch): a lost device
        }
    }
}

std::vector<std::size_t> Renderer::lodTriangles() const {
    std::vector<std::size_t> n{mScene.triangleCount()};
    for (const auto& [level, bvh] : mCoarser)
        n.push_back(level.triangleCount());
    return n;
}

vk::Context& Renderer::context() noexcept {
    return *mCtx;
}
const scene::Scene& Renderer::scene() const noexcept {
    return mScene;
}
const scene::BvhBuildStats& Renderer::bvhStats() const noexcept {
    return mBvh->stats();
}
std::pair<scene::DynamicGeometry*, trace::GpuScene*> Renderer::moving(SceneId id) const {
    if (id == 0) return {mDynamic.get(), mGpuScene.get()};
    if (id > mMoreScenes.size()) throw Error("renderer: no scene " + std::to_string(id));
    const LoadedScene& s = *mMoreScenes[id - 1];
    return {s.dynamic.get(), s.gpu.get()};
}

void Renderer::setSceneTime(double seconds) {
    // Going back in time (a seek, a loop the caller restarts) or the first pose: no motion.
    const bool cut = !mScenePosed || seconds < mSceneTime;
    for (SceneId id = 0; id < sceneCount(); ++id) {
        const auto [dynamic, gpu] = moving(id);
        if (dynamic == nullptr) continue;
        if (cut) {
            dynamic->reset(seconds);
        } else {
            dynamic->update(seconds);
        }
        // Packed on the host only: renderFrame() writes the copy of the frame ring's next slot
        // once the ring has waited for that slot's last frame.
        gpu->update(*dynamic);
    }
    mSceneTime = seconds;
    mScenePosed = true;
}

bool Renderer::animated() const noexcept {
    for (SceneId id = 0; id < sceneCount(); ++id) {
        if (scene(id).animated()) return true;
    }
    return false;
}

scene::Camera Renderer::sceneCamera(SceneId id) const {
    scene::Camera camera = scene(id).camera;
    const scene::DynamicGeometry* dynamic = moving(id).first;
    if (dynamic == nullptr || dynamic->rig().cameraNode < 0) return camera;
    // A glTF camera looks down its node's -Z with +Y up (glTF 2.0, 3.10.1).
    const glm::mat4& world =
        dynamic->pose().world.at(static_cast<std::size_t>(dynamic->rig().cameraNode));
    camera.position = glm::vec3(world[3]);
    camera.forward = glm::normalize(glm::vec3(world * glm::vec4(0.0f, 0.0f, -1.0f, 0.0f)));
    camera.up = glm::normalize(glm::vec3(world * glm::vec4(0.0f, 1.0f, 0.0f, 0.0f)));
    return camera;
}

const scene::DynamicGeometry* Renderer::dynamicGeometry(SceneId id) const {
    return moving(id).first;
}

MethodContext Renderer::methodContext() const noexcept {
    return {*mCtx, *mGpuScene, *mHistory};
}

Renderer::SceneId Renderer::addScene(const std::string& spec, const scene::GltfLoadOptions& load) {
    auto loaded = std::make_unique<LoadedScene>();
    loaded->scene = loadLevels(spec, load, loaded->coarser);
    loaded->bvh.emplace(loaded->scene);
    loaded->dynamic = makeDynamic(loaded->scene, mAnimation, mSceneTime);
    loaded->gpu = uploadLevels(*mCtx, loaded->scene, *loaded->bvh, loaded->coarser,
                               loaded->dynamic.get(), mRing->framesInFlight());
    mMoreScenes.push_back(std::move(loaded));
    return mMoreScenes.size();
}

const scene::Scene& Renderer::scene(SceneId id) const {
    if (id == 0) return mScene;
    if (id > mMoreScenes.size()) throw Error("renderer: no scene " + std::to_string(id));
    return mMoreScenes[id - 1]->scene;
}

MethodContext Renderer::methodContext(SceneId id) const {
    if (id == 0) return methodContext();
    if (id > mMoreScenes.size()) throw Error("renderer: no scene " + std::to_string(id));
    return {*mCtx, *mMoreScenes[id - 1]->gpu, *mHistory};
}
uint32_t Renderer::framesInFlight() const noexcept {
    return mRing->framesInFlight();
}

void Renderer::resetHistory(const std::string& view) {
    // The view's TAA and whatever history its method keeps (layers: one per layer).
    if (view.empty()) {
        mHistory->invalidateAll();
    } else {
        mHistory->invalidatePrefix(view + ".");
    }
    mViewHistory.erase(view);
}

void Renderer::resetHistory() {
    mHistory->invalidateAll();
    mViewHistory.clear();
}

std::vector<rg::CompletedFrame> Renderer::takeCompleted() {
    return mRing->takeCompleted();
}

void Renderer::waitIdle() {
    mRing->waitIdle();
}

VkDeviceSize Renderer::frameImageBytes(std::optional<VkExtent2D> extent) const noexcept {
    return mHistory->imageBytes(extent) + mRing->transientImageBytes(extent);
}

// An untimed frame through the method's pipelines and the tone mapper, into a throwaway pool,
// waited for, never touching the history.
void Renderer::runWarmUp(const WarmUp& warm) {
    rg::TransientPool pool(*mCtx);
    rg::RenderGraph graph(warm.width, warm.height);
    const rg::TextureId ldr = mTonemap->add(graph, warm.addRadiance(graph), mScene.exposure);
    graph.sink(ldr, rg::Access::StorageRead);
    (void)graph.executeAndWait(graph.compile(), pool);
}

namespace {
// Every view has a method, a target, a size, a valid frustum and a name of its own.
void checkViews(std::span<const View> views, std::span<OutputTarget* const> targets) {
    if (views.empty() || views.size() != targets.size()) {
        throw Error("renderFrame: " + std::to_string(views.size()) + " view(s) and " +
                    std::to_string(targets.size()) + " target(s)");
    }
    for (std::size_t i = 0; i < views.size(); ++i) {
        const View& v = views[i];
        if (v.method == nullptr || targets[i] == nullptr || v.width == 0 || v.height == 0) {
            throw Error("renderFrame: view '" + v.name + "' lacks a method, a target or a size");
        }
        if (v.frustum && !v.frustum->valid()) {
            throw Error("renderFrame: view '" + v.name + "' has an empty or non-finite frustum");
        }
        for (std::size_t j = 0; j < i; ++j) {
            if (views[j].name == v.name) {
                throw Error("renderFrame: two views are named '" + v.name + "'");
            }
        }
    }
}
} // namespace

rg::TextureId Renderer::addTaa(rg::RenderGraph& graph, const View& v, const MethodImage& made,
                               const shaders::trace::CameraPush& camera,
                               HistoryUpdates& nextHistory) {
    const rg::HistoryTextures history = graph.importHistory(
        *mHistory, kTaaHistory, VK_FORMAT_R32G32B32A32_SFLOAT, v.width, v.height);
    const auto it = mViewHistory.find(v.name);
    const bool known = it != mViewHistory.end() && it->second.valid;
    std::optional<passes::TaaSupport> support;
    if (made.support && v.post.taaSettings.supportWeighted && v.post.taaSettings.adaptive) {
        support = passes::TaaSupport{*made.support,
                                     graph.importHistory(*mHistory, kTaaWeightHistory,
                                                         VK_FORMAT_R32_SFLOAT, v.width, v.height)};
    }
    std::optional<passes::TaaMotion> motion;
    if (made.motion) {
        motion =
            passes::TaaMotion{*made.motion,
                              graph.importHistory(*mHistory, kTaaSignatureHistory,
                                                  passes::kTaaSignatureFormat, v.width, v.height),
                              v.post.taaSettings};
    }
    // The weight sums and signatures stand for the colour history only if last frame
    // wrote them too (a method or setting switched since leaves them stale): else
    // start afresh.
    const bool pooledBefore = known && it->second.pooled;
    const bool movedBefore = known && it->second.motion;
    const bool reset =
        passes::taaMustReset(known && history.valid, v.saccade, v.gaze,
                             known ? it->second.gaze : v.gaze, v.width, v.post.taaSettings) ||
        (support && !pooledBefore) || (motion && !movedBefore);
    const shaders::trace::CameraPush previous = known ? it->second.camera : camera;
    const passes::TaaFrameState state{v.exposure, v.gaze, v.method->gazeDependent(),
                                      known && it->second.gaze == v.gaze,
                                      known ? it->second.samples : 0u};
    const rg::TextureId out = mTaa->add(graph, history, made.radiance, camera, previous, reset,
                                        v.post.taaSettings, state, support, motion);
    nextHistory.emplace_back(v.name,
                             ViewHistory{camera, v.gaze, true,
                                         passes::TaaPass::nextSamples(camera, previous, reset,
                                                                      v.post.taaSettings, state),
                                         support.has_value(), motion.has_value()});
    return out;
}

void Renderer::addView(rg::RenderGraph& graph, const View& v, OutputTarget& target,
                       HistoryUpdates& nextHistory) {
    MethodImage made = v.method->addRadiance(graph, v);
    const shaders::trace::CameraPush camera = v.cameraPush();
    const bool panel = v.method->rendersPanel(v);
    const bool pointsOnly = v.post.denoise &&
                            v.post.denoise->placement == passes::DenoisePlacement::Points &&
                            v.method->denoisesPoints(v);
    if (v.post.denoise && !panel && !pointsOnly) {
        made.radiance = mDenoise->add(graph, made.radiance, camera, v.gaze, *v.post.denoise);
    }
    rg::TextureId image = made.radiance;
    if (v.post.taa && !panel && !v.method->accumulates()) {
        image = addTaa(graph, v, made, camera, nextHistory);
    }
    rg::TextureId ldr = mTonemap->add(graph, image, v.exposure);
    if (v.post.lens) {
        display::LensModel lens = v.post.lens->model;
        if (panel) {
            // Already the panel's image (green): only red and blue still need their
            // radial shift relative to green, c + (q - c) chroma.
            lens.k1 = lens.k2 = 0.0f;
            lens.chroma /= lens.chroma.g;
        }
        ldr = mLens->add(graph, ldr, lens, v.post.lens->centre, panel);
    }
    target.addOutput(graph, ldr, v);
}

FrameResult Renderer::renderFrame(std::span<const View> views,
                                  std::span<OutputTarget* const> targets,
                                  const FrameOptions& options) {
    const auto t = Clock::now();
    checkViews(views, targets);
    for (const View& v : views) {
        if (const std::optional<WarmUp> warm = v.method->warmUp(v)) {
            runWarmUp(*warm);
        }
    }

    rg::FrameRing::Frame& frame = mRing->begin();
    // The ring has waited for this slot's last frame: its copy of each moving scene's tables is
    // free to take the latest pose.
    const auto slot = static_cast<uint32_t>(frame.number % mRing->framesInFlight());
    for (SceneId id = 0; id < sceneCount(); ++id) {
        if (trace::GpuScene* gpu = moving(id).second; gpu->dynamic()) gpu->prepare(slot);
    }
    mHistory->setFrameNumber(frame.number);
    rg::RenderGraph graph(views.front().width, views.front().height);
    // Each distinct target once (both eyes may go to one window).
    std::vector<OutputTarget*> distinct;
    for (OutputTarget* target : targets) {
        if (std::find(distinct.begin(), distinct.end(), target) == distinct.end()) {
            distinct.push_back(target);
        }
    }
    for (OutputTarget* target : distinct) {
        target->beginFrame(graph);
    }
    FrameResult result;
    result.number = frame.number;
    HistoryUpdates nextHistory;
    for (std::size_t i = 0; i < views.size(); ++i) {
        const View& v = views[i];
        auto add = [&] { addView(graph, v, *targets[i], nextHistory); };
        if (!v.name.empty()) {
            const rg::RenderGraph::Scope scope = graph.scope(v.name, v.width, v.height);
            add();
        } else if (views.size() > 1) {
            throw Error("renderFrame: with several views each needs a name");
        } else {
            add();
        }
        result.views.push_back({v.method->rays(v)});
    }
    for (OutputTarget* target : distinct) {
        target->endFrame(graph);
    }
    const rg::CompiledGraph compiled = graph.compile();
    if (options.graphviz) {
        result.dot = graph.toDot(compiled);
    }
    frame.recorded =
        graph.record(compiled, *frame.pool,
                     frame.timestamps(rg::RenderGraph::timestampCount(compiled)), frame.cmd);
    rg::SubmitSync sync;
    bool wait = mRing->framesInFlight() == 1;
    for (OutputTarget* target : distinct) {
        target->addSync(sync);
        wait = wait || target->waitsForFrame();
    }
    mRing->submit(sync);
    // Submitted: this frame's history is what the next frame reads.
    mHistory->commit(graph);
    for (auto& [name, h] : nextHistory) {
        mViewHistory[name] = h;
    }
    std::vector<FoveationMethod*> methods;
    for (const View& v : views) {
        if (std::find(methods.begin(), methods.end(), v.method) == methods.end()) {
            methods.push_back(v.method);
            v.method->frameSubmitted();
        }
    }
    if (wait) {
        mRing->waitIdle();
        for (const rg::CompletedFrame& c : mRing->takeCompleted()) {
            if (c.number == frame.number) {
                result.timings = c.timings;
            }
        }
        for (OutputTarget* target : distinct) {
            target->frameFinished();
        }
    }
    result.wallMs = msSince(t);
    return result;
}

} // namespace gt::render
