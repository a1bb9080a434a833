#include "eccentricity_layers.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

#include "core/error.hpp"
#include "scene/subdivision.hpp"
#include "view.hpp"

namespace gt::render {

namespace {
constexpr const char* kLayerHistory = "layers.history";
constexpr const char* kLayerSignatureHistory = "layers.signature"; // a scene that moves
constexpr VkFormat kLayerFormat = VK_FORMAT_R32G32B32A32_SFLOAT;

std::string layerScope(std::size_t i) {
    return "layer" + std::to_string(i + 1);
}
} // namespace

EccentricityLayers::EccentricityLayers(const MethodContext& mc, EccentricityLayerSettings s)
    : mMc(mc), mSettings(std::move(s)), mPass(mc.ctx), mTaa(mc.ctx) {
    if (!(mSettings.slope > 0.0)) {
        throw ArgumentError("MAR slope " + std::to_string(mSettings.slope) + " is not positive");
    }
    if (mSettings.layers < 1 || mSettings.layers > passes::kMaxEccentricityLayers) {
        throw ArgumentError("layer count " + std::to_string(mSettings.layers) + " is outside 1.." +
                            std::to_string(passes::kMaxEccentricityLayers));
    }
    if (mSettings.raysPerPixel == 0) {
        throw ArgumentError("rays per layer pixel is 0: every layer pixel traces at least 1 ray");
    }
    if (!(mSettings.transition > 0.0f) || mSettings.transition > 1.0f) {
        throw ArgumentError("layer blend transition must be in (0, 1]");
    }
}

const LayerLayout& EccentricityLayers::layout(const View& view) {
    const trace::FrustumTangents t = tangentsOf(view.cameraPush());
    auto q = [](float v) { return std::lround(static_cast<double>(v) * 1e4); };
    const LayoutKey key{view.width, view.height, q(t.left), q(t.right), q(t.up), q(t.down)};
    auto it = mLayouts.find(key);
    if (it == mLayouts.end()) {
        const foveation::LayerDisplay display =
            mSettings.display ? foveation::LayerDisplay::fromProfile(foveation::windowProfile(
                                    *mSettings.display, view.width, view.height))
                              : viewDisplay(view.width, view.height, t);
        const foveation::MarModel mar{mSettings.slope};
        it = mLayouts
                 .emplace(
                     key,
                     mSettings.radiiDeg.empty()
                         ? layoutLayers(view.width, view.height, display, mar, mSettings.layers)
                         : layoutLayers(view.width, view.height, display, mar, mSettings.radiiDeg))
                 .first;
    }
    return it->second;
}

MethodImage EccentricityLayers::addRadiance(rg::RenderGraph& graph, const View& view) {
    const LayerLayout& lay = layout(view);
    const std::size_t n = lay.grids.size();
    const shaders::trace::CameraPush viewCamera = view.cameraPush();
    const trace::FrustumTangents tangents = tangentsOf(viewCamera);
    ViewState prev = mViews.count(view.name) ? mViews.at(view.name) : ViewState{};
    if (prev.layers.size() != n) {
        prev.layers.assign(n, LayerState{});
    }
    // A saccade, or a gaze jump the tracker did not report: every layer starts afresh around
    // the new gaze, so the fovea is sharp at once.
    const bool reset =
        passes::taaMustReset(prev.known, view.saccade, view.gaze,
                             prev.known ? prev.gaze : view.gaze, view.width, mSettings.taa);

    Pending p;
    p.state = prev;
    p.state.gaze = view.gaze;
    p.state.known = true;
    p.traced.assign(n, false);
    std::vector<passes::ComposedLayer> composed;
    for (std::size_t i = 0; i < n; ++i) {
        const LayerGrid& grid = lay.grids[i];
        const LayerState& last = prev.layers[i];
        const rg::RenderGraph::Scope scope = graph.scope(layerScope(i), grid.width, grid.height);
        // The history holds this layer's grid: not after a reset, nor after a resize (a
        // half-rate layer must not read a history the new size has just replaced).
        const bool kept = last.valid && mMc.history.holds(graph.scopedName(kLayerHistory),
                                                          grid.width, grid.height, kLayerFormat);
        // Half rate (section 4.3): the inner layer every frame, the others on alternate frames,
        // staggered so that one of them is traced on even frames and the next on odd ones. Not
        // in a scene that moves: a layer left untraced shows its objects where they were.
        const bool due = i == 0 || !mSettings.halfRate || mMc.scene.dynamic() || reset || !kept ||
                         (prev.frame + i) % 2 == 0;
        rg::TextureId image;
        LayerRect rect = last.rect;
        if (due) {
            // Rays through the jittered grid; the history and the compose step on the grid
            // itself (without a history, where the rays went).
            // Each layer walks the jitter sequence by its own count: a half-rate layer sampling
            // every other entry would cover only half of its pixel.
            const uint64_t traces = kept ? last.traces : 0;
            const glm::vec2 jitter = mSettings.jitter ? layerJitter(traces) : glm::vec2(0.0f);
            const LayerRect grid0 = placeLayer(grid, view.width, view.height, view.gaze);
            const LayerRect rays = jittered(grid0, grid.pitch, jitter);
            rect = mSettings.temporal ? grid0 : rays;
            auto cameraThrough = [&](const LayerRect& r) {
                return trace::cameraPush(view.camera,
                                         subFrustum(tangents, view.width, view.height, r));
            };
            const shaders::trace::CameraPush camera = cameraThrough(rect);
            const uint32_t lod =
                mSettings.lod ? scene::lodForPitch(grid.pitch, mMc.scene.lodLevels()) : 0;
            const passes::TracedLayer traced =
                mPass.addTraceImage(graph, mMc.scene, cameraThrough(rays), grid.width, grid.height,
                                    mSettings.raysPerPixel, lod);
            const rg::HistoryTextures history = graph.importHistory(
                mMc.history, kLayerHistory, kLayerFormat, grid.width, grid.height);
            const bool fresh = reset || !mSettings.temporal || !kept;
            const bool still = !fresh && passes::sameCamera(camera, last.camera);
            passes::TaaSettings blend = mSettings.taa;
            const auto movingCap = static_cast<uint32_t>(std::lround(1.0f / blend.currentWeight));
            uint32_t samples = fresh ? 0 : last.samples;
            if (still) {
                samples = std::min(samples, mSettings.maxStillSamples - 1);
                blend.clipGamma = 1e30f;      // nothing moved: the history is this grid's
                blend.depthTolerance = 1e30f; // and the jitter changes distances, not surfaces
            } else {
                samples = std::min(samples, movingCap - 1);
                blend.depthTolerance *= grid.pitch;
            }
            blend.currentWeight = 1.0f / static_cast<float>(samples + 1);
            // A scene that moves: the layer's history follows each hit's motion and is
            // rejected where its surface or shadow changed (taa.glsl), as the view's TAA.
            std::optional<passes::TaaMotion> motion;
            if (traced.motion) {
                passes::TaaSettings moving = mSettings.taa;
                moving.depthTolerance *= grid.pitch;
                motion = passes::TaaMotion{*traced.motion,
                                           graph.importHistory(mMc.history, kLayerSignatureHistory,
                                                               passes::kTaaSignatureFormat,
                                                               grid.width, grid.height),
                                           moving};
            }
            image = mTaa.add(graph, history, traced.radiance, camera, kept ? last.camera : camera,
                             fresh, blend, std::nullopt, std::nullopt, motion);
            p.state.layers[i] = {rect, camera, true, traces + 1, samples + 1};
            p.traced[i] = true;
            p.rays += static_cast<uint64_t>(grid.width) * grid.height * mSettings.raysPerPixel;
        } else {
            image =
                graph.readHistory(mMc.history, kLayerHistory, kLayerFormat, grid.width, grid.height)
                    .previous;
        }
        composed.push_back({image, rect.origin, grid.pitch, grid.radiusPx});
    }
    mPending[view.name] = std::move(p);
    return mPass.addCompose(graph, composed, view.gaze, mSettings.transition);
}

uint64_t EccentricityLayers::rays(const View& view) const {
    if (const auto it = mPending.find(view.name); it != mPending.end()) {
        return it->second.rays;
    }
    if (const auto it = mLast.find(view.name); it != mLast.end()) {
        return it->second.rays;
    }
    return 0;
}

std::vector<bool> EccentricityLayers::tracedLastFrame(const View& view) const {
    if (const auto it = mPending.find(view.name); it != mPending.end()) {
        return it->second.traced;
    }
    if (const auto it = mLast.find(view.name); it != mLast.end()) {
        return it->second.traced;
    }
    return {};
}

void EccentricityLayers::frameSubmitted() {
    for (auto& [name, p] : mPending) {
        p.state.frame += 1;
        mViews[name] = p.state;
        mLast[name] = std::move(p);
    }
    mPending.clear();
}

std::optional<WarmUp> EccentricityLayers::warmUp(const View& view) {
    if (mWarm) {
        return std::nullopt;
    }
    mWarm = true;
    // trace -> taa -> compose once at 16 x 16 with a throwaway history, composing as many
    // layers as the view has (the compose pipeline is specialised on the count).
    auto pool = std::make_shared<rg::HistoryPool>(mMc.ctx);
    const shaders::trace::CameraPush cam = view.cameraPush();
    const std::size_t n = layout(view).grids.size();
    return WarmUp{16, 16, [this, pool, cam, n](rg::RenderGraph& g) {
                      std::vector<passes::ComposedLayer> layers;
                      for (std::size_t i = 0; i < n; ++i) {
                          const rg::RenderGraph::Scope scope = g.scope(layerScope(i), 16, 16);
                          rg::TextureId image = mPass.addTrace(g, mMc.scene, cam, 16, 16, 1);
                          if (i == 0) {
                              const rg::HistoryTextures h =
                                  g.importHistory(*pool, kLayerHistory, kLayerFormat, 16, 16);
                              image = mTaa.add(g, h, image, cam, cam, true, mSettings.taa);
                          }
                          layers.push_back({image, {}, 1.0f, 8.0f});
                      }
                      return mPass.addCompose(g, layers, glm::vec2(8.0f), mSettings.transition);
                  }};
}

} // namespace gt::render
