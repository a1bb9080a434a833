#include "point_set_method.hpp"

#include <chrono>
#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/progress.hpp"
#include "foveation/point_set_cache.hpp"
#include "view.hpp"

namespace gt::render {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

foveation::PointSet loadPointSet(const foveation::PointSetParams& params,
                                 const std::filesystem::path& cacheDir, double& ms) {
    const auto t = Clock::now();
    // Generating a set for a large display takes seconds; loading one from the cache does not.
    // A view never traces more points than its screen has pixels (point_set_cap.hpp).
    progress::Step step("generating the point set", 1000);
    foveation::CachedPointSet c =
        foveation::loadOrGenerateForView(cacheDir, params, [&](double f) { (void)step.reach(f); });
    if (!c.warning.empty()) {
        log::warn(c.warning);
    }
    if (!c.thinned.empty()) {
        log::info(c.thinned);
    }
    ms = msSince(t);
    return std::move(c.set);
}
} // namespace

void useThesisReconstruction(PointSetSettings& settings, passes::TaaSettings& taa) {
    settings.displayReferred = false;
    settings.jitter = false;
    settings.pixelRays = false;
    settings.interpolation.shepardPower = 1.0f;
    settings.interpolation.edgeTolerance = 0.0f;
    settings.interpolation.rangeSigma = 0.0f;
    taa.adaptive = false;
}

void useNoisySampleWeights(passes::InterpolateSettings& s) {
    s.shepardPower = 1.0f;
    s.rangeSigma = 0.0f;
}

PointSetMethod::PointSetMethod(const MethodContext& mc, const foveation::PointSetParams& params,
                               const std::filesystem::path& cacheDir)
    : PointSetMethod(mc, [&] {
          // Timed here and handed on: a member written while mPoints is built would be reset
          // by its own initialiser afterwards.
          TimedSet t{.set = {}, .ms = 0.0};
          t.set = loadPointSet(params, cacheDir, t.ms);
          return t;
      }()) {}

PointSetMethod::PointSetMethod(const MethodContext& mc, TimedSet loaded)
    : PointSetMethod(mc, std::move(loaded.set), loaded.ms) {}

PointSetMethod::PointSetMethod(const MethodContext& mc, foveation::PointSet points,
                               double pointSetMs)
    : mMc(mc), mPoints(std::move(points)),
      mNeighbours(mPoints, foveation::NeighbourIndex::kMaxNeighbours),
      mGpuPoints(mc.ctx, mPoints, mNeighbours, foveation::GpuPointSet::Index::OnDemand),
      mPointSample(mc.ctx), mInterpolate(mc.ctx), mRbfSolve(mc.ctx), mPointDenoise(mc.ctx),
      mPointSetMs(pointSetMs) {
    mNeighbourMs = mNeighbours.buildSeconds() * 1e3;
    mNeighbourMb = static_cast<double>(mNeighbours.bytes()) / 1e6;
}

PointSetMethod::~PointSetMethod() = default;

std::size_t PointSetMethod::pointsSampled(glm::vec2 gaze) const {
    const auto w = mPoints.params().display.width, h = mPoints.params().display.height;
    const glm::vec2 off = passes::gazeOffset(gaze, w, h);
    // renderFrame asks every frame for every view (and the demo's overlay once more): a pass
    // over the whole set. The offset moves in whole pixels, so the last answer usually holds.
    if (!mSampledMemo || mSampledMemo->first != off) {
        mSampledMemo.emplace(off, mPoints.countOnScreen(off.x + static_cast<float>(w),
                                                        off.y + static_cast<float>(h),
                                                        passes::kSampleMargin));
    }
    return mSampledMemo->second;
}

passes::InterpolateSettings PointSetMethod::interpolation() const {
    passes::InterpolateSettings s = settings.interpolation;
    if (!supportsTaa() && settings.noisySampleWeights) {
        useNoisySampleWeights(s);
    }
    return s;
}

float PointSetMethod::foveaRadiusPx() const {
    if (settings.foveaRaysPerPoint == 0) return 0.0f;
    const auto& d = mPoints.params().display;
    // v (thesis eq. 1) is the viewing distance in display widths.
    return static_cast<float>(d.viewingDistance * d.width *
                              std::tan(settings.foveaDeg * std::numbers::pi / 180.0));
}

std::size_t PointSetMethod::pointsWithin(const View& view, float radius) const {
    const auto w = mPoints.params().display.width, h = mPoints.params().display.height;
    const glm::vec2 off = passes::gazeOffset(sampledGaze(view), w, h);
    if (!mFoveaMemo || mFoveaMemo->first != glm::vec3(off, radius)) {
        mFoveaMemo.emplace(glm::vec3(off, radius),
                           mPoints.countOnScreenWithin(off.x + static_cast<float>(w),
                                                       off.y + static_cast<float>(h), radius,
                                                       passes::kSampleMargin));
    }
    return mFoveaMemo->second;
}

uint64_t PointSetMethod::rays(const View& view) const {
    const glm::vec2 gaze = sampledGaze(view);
    const uint64_t all = static_cast<uint64_t>(pointsSampled(gaze)) * settings.raysPerPoint;
    const float radius = foveaRadiusPx();
    if (radius <= 0.0f) return all;
    const auto fovea = static_cast<int64_t>(pointsWithin(view, radius));
    return static_cast<uint64_t>(static_cast<int64_t>(all) +
                                 fovea * (static_cast<int64_t>(settings.foveaRaysPerPoint) -
                                          static_cast<int64_t>(settings.raysPerPoint)));
}

std::optional<passes::PanelWarp> PointSetMethod::warpFor(const View& view) const {
    if (!settings.displaySpace || !view.post.lens) return std::nullopt;
    return passes::PanelWarp{view.post.lens->model, view.post.lens->centre};
}

bool PointSetMethod::rendersPanel(const View& view) const {
    return warpFor(view).has_value();
}

glm::vec2 PointSetMethod::sampledGaze(const View& view) const {
    const std::optional<passes::PanelWarp> warp = warpFor(view);
    if (!warp) return view.gaze;
    const glm::vec2 size(static_cast<float>(view.width), static_cast<float>(view.height));
    return warp->lens.displayOf(view.gaze / size, warp->centre, size.x / size.y) * size;
}

// The thesis's per-pixel table, and for RBF its per-pixel weights, when the settings ask for
// them: built on the CPU once per k (and RBF kernel and shape).
passes::InterpolateInputs PointSetMethod::tableInputs(const passes::InterpolateSettings& s) {
    if (!passes::usesPixelTable(s)) {
        // Hundreds of MB: give them back to whatever runs next.
        mKnnTable.reset();
        mRbfPixelWeights.reset();
        return {};
    }
    std::optional<foveation::PixelKnnTable> table;
    if (!mKnnTable || mKnnTable->k() != s.k) {
        mKnnTable.reset();
        mRbfPixelWeights.reset();
        table.emplace(mPoints, mNeighbours, s.k);
        mKnnTable.emplace(mMc.ctx, *table);
        // The GPU's bytes: the flat table's where it fits (knnLayoutFor), else the compact one's.
        mKnnTablePrepared = {table->buildSeconds() * 1e3,
                             static_cast<double>(mKnnTable->bytes()) / 1e6};
    }
    if (s.method != passes::Interpolation::Rbf) {
        mRbfPixelWeights.reset();
        return {std::nullopt, &*mKnnTable, nullptr};
    }
    if (!mRbfPixelWeights || mRbfPixelWeights->kernel() != s.kernel ||
        mRbfPixelWeights->shape() != s.rbfShape) {
        mRbfPixelWeights.reset();
        if (!table) {
            table.emplace(mPoints, mNeighbours, s.k); // same k, another kernel or shape
        }
        const foveation::RbfPixelWeights weights(mPoints, *table, s.kernel, s.rbfShape);
        mRbfPixelWeights.emplace(mMc.ctx, weights);
        mRbfPrepared = {weights.buildSeconds() * 1e3, static_cast<double>(weights.bytes()) / 1e6};
    }
    return {std::nullopt, &*mKnnTable, &*mRbfPixelWeights};
}

const foveation::GpuRbfInverse& PointSetMethod::inverseFor(const passes::InterpolateSettings& s) {
    if (!mRbfInverse || mRbfInverse->k() != s.k || mRbfInverse->kernel() != s.kernel ||
        mRbfInverse->shape() != s.rbfShape) {
        mRbfInverse.reset();
        const foveation::RbfInverse inv =
            foveation::buildRbfInverse(mPoints, mNeighbours, s.k, s.kernel, s.rbfShape);
        mRbfInverse.emplace(mMc.ctx, inv);
        mRbfPrepared = {inv.seconds * 1e3,
                        static_cast<double>(inv.inverse.size() * sizeof(float)) / 1e6};
    }
    return *mRbfInverse;
}

// Chunks pay where most of the set is off screen: on lavapipe (fove, market, nn) they took
// point_sample from 652 to 439 ms with the gaze in a corner (26 % of the set on screen), but
// with it centred (71 %) from 1871 to 1785 ms at 1 ray and from 4471 to 4954 ms at 8, each ray
// costing more through the chunk list than they save.
passes::PointDispatch PointSetMethod::dispatchFor(glm::vec2 gaze, float siteJitter) const {
    const bool mostlyOff = static_cast<double>(pointsSampled(gaze)) <
                           kChunkedShare * static_cast<double>(mPoints.points().size());
    return settings.onScreenChunks && siteJitter == 0.0f && mostlyOff
               ? passes::PointDispatch::OnScreenChunks
               : passes::PointDispatch::WholeSet;
}

// point_sample -> (point_denoise) -> (rbf_solve) -> interpolate, with `rays` per point traced by
// `lanes` threads.
passes::InterpolatedImage PointSetMethod::addImage(
    rg::RenderGraph& graph, const shaders::trace::CameraPush& camera, glm::vec2 gaze, uint32_t rays,
    uint32_t lanes, const passes::InterpolateInputs& prepared,
    const std::optional<passes::PanelWarp>& warp, passes::InterpolateSettings s, uint32_t frame,
    float siteJitter, const std::optional<PointDenoising>& denoise) {
    // Modified Shepard blends from the sites of this frame. RBF's weights were solved for the
    // fixed ones; nearest neighbour keeps them too, since its exact per-pixel nearest point is
    // what makes it the cheap real-time choice (moving them cost 7x: 239 ms against 34 ms at
    // 1280x1440 on lavapipe).
    const bool moveSites = frame > 0 && s.method == passes::Interpolation::Shepard;
    s.siteFrame = moveSites ? frame : 0u;
    s.siteJitter = moveSites ? siteJitter : 0.0f;
    // The neighbour index goes to the GPU the first time a pass reads it, and stays.
    if (passes::readsNeighbourIndex(s) || denoise) {
        mGpuPoints.uploadIndex(mMc.ctx, mNeighbours);
    }
    const passes::SampledPoints sampled = mPointSample.addSamples(
        graph, mMc.scene, camera, mGpuPoints, gaze, rays, lanes, warp ? &*warp : nullptr,
        settings.lod, frame, s.siteJitter, !settings.pixelRays, dispatchFor(gaze, s.siteJitter),
        settings.integrator, {settings.foveaRaysPerPoint, foveaRadiusPx()});
    const rg::BufferId samples =
        denoise ? mPointDenoise.add(graph, mGpuPoints, {sampled.samples, sampled.guide},
                                    {camera, gaze, frame, s.siteJitter, warp ? &*warp : nullptr},
                                    denoise->settings, denoise->history)
                : sampled.samples;
    passes::InterpolateInputs in = prepared;
    if (passes::usesRbfSolve(s)) {
        in.lambdas = mRbfSolve.add(graph, mGpuPoints, inverseFor(s), samples, gaze, s);
    }
    return mInterpolate.add(graph, mGpuPoints, samples, gaze, s, in, sampled.motion);
}

MethodImage PointSetMethod::addRadiance(rg::RenderGraph& graph, const View& view) {
    const auto& d = mPoints.params().display;
    if (view.width != d.width || view.height != d.height) {
        throw Error("view '" + view.name + "' is " + std::to_string(view.width) + "x" +
                    std::to_string(view.height) + " but its point set was built for " +
                    std::to_string(d.width) + "x" + std::to_string(d.height));
    }
    const passes::InterpolateInputs prepared = tableInputs(settings.interpolation);
    const uint32_t lanes = passes::pointSampleLanes(mMc.ctx, settings.raysPerPoint);
    passes::InterpolateSettings s = interpolation();
    s.displayExposure = settings.displayReferred ? view.exposure : 0.0f;
    // A still camera whose frames TAA pools by their support (taa.glsl) gains from sites that
    // roam their whole neighbourhood; a moving one, whose history is only reprojected, from
    // smaller moves that flicker less.
    const shaders::trace::CameraPush camera = view.cameraPush();
    const auto found = mLastFrame.find(view.name);
    const std::optional<LastFrame> last =
        found != mLastFrame.end() ? std::optional<LastFrame>(found->second) : std::nullopt;
    const bool pooled = view.post.taa && view.post.taaSettings.adaptive &&
                        view.post.taaSettings.supportWeighted && supportsTaa() && last &&
                        passes::sameCamera(last->camera, camera);
    const shaders::trace::CameraPush previous = last ? last->camera : camera;
    const glm::vec2 gaze = sampledGaze(view);
    mLastFrame.insert_or_assign(view.name, LastFrame{camera, gaze});
    const passes::InterpolatedImage image =
        addImage(graph, camera, gaze, settings.raysPerPoint, lanes, prepared, warpFor(view), s,
                 settings.jitter ? mFrame : 0u, pooled ? kSiteJitterStill : kSiteJitterMoving,
                 pointDenoiseFor(view, last));
    if (s.method == passes::Interpolation::ViewMotion) {
        if (!mMotionView) {
            mMotionView = std::make_unique<passes::MotionViewPass>(mMc.ctx);
        }
        return {mMotionView->add(graph, image.radiance, image.motion, camera, previous),
                std::nullopt, image.motion};
    }
    // The support says something only where the sites move from frame to frame.
    const std::optional<rg::TextureId> support =
        settings.jitter && s.method == passes::Interpolation::Shepard && supportsTaa()
            ? std::optional<rg::TextureId>(image.support)
            : std::nullopt;
    if (settings.edgeRays && image.motion) {
        if (!mEdgeRays) {
            mEdgeRays = std::make_unique<passes::EdgeRaysPass>(mMc.ctx);
        }
        const passes::EdgeRaysImage edged = mEdgeRays->add(
            graph, mMc.scene, camera, {image.radiance, *image.motion, support}, mFrame);
        return {edged.radiance, edged.support, edged.motion};
    }
    return {image.radiance, support, image.motion};
}

bool PointSetMethod::denoisesPoints(const View& view) const {
    return settings.integrator.integrator == trace::Integrator::Path && view.post.denoise &&
           view.post.denoise->placement != passes::DenoisePlacement::Image;
}

std::optional<PointSetMethod::PointDenoising>
PointSetMethod::pointDenoiseFor(const View& view, const std::optional<LastFrame>& last) const {
    if (!denoisesPoints(view)) {
        return std::nullopt;
    }
    passes::PointDenoiseSettings d;
    d.neighbours = std::min(d.neighbours, mGpuPoints.storedNeighbours());
    d.foveaDeg = view.post.denoise->foveaDeg; // the image denoiser's fovea, kept sharp alike
    d.fullDeg = view.post.denoise->fullDeg;
    d.temporalAlpha = view.post.denoise->pointTemporalAlpha;
    PointDenoising denoising{d, std::nullopt};
    denoising.history.emplace(
        passes::PointDenoiseHistory{mMc.history, last ? std::optional(last->camera) : std::nullopt,
                                    last ? last->gaze : glm::vec2(0.0f)});
    return denoising;
}

std::optional<WarmUp> PointSetMethod::warmUp(const View& view) {
    const passes::InterpolateSettings s = interpolation();
    const uint32_t lanes = passes::pointSampleLanes(mMc.ctx, settings.raysPerPoint);
    const auto variant = std::make_tuple(s.method, passes::usesPixelTable(s), lanes);
    if (mWarm.contains(variant)) {
        return std::nullopt;
    }
    mWarm.insert(variant);
    // Full size, one ray per point, through every pipeline the timed frame uses. The lanes stay
    // those of the timed frame: idle lanes cost little and trace nothing.
    const passes::InterpolateInputs prepared = tableInputs(s);
    const shaders::trace::CameraPush cam = view.cameraPush();
    const glm::vec2 gaze = sampledGaze(view);
    const std::optional<passes::PanelWarp> warp = warpFor(view);
    return WarmUp{view.width, view.height,
                  [this, cam, gaze, lanes, prepared, warp, s](rg::RenderGraph& g) {
                      return addImage(g, cam, gaze, 1, lanes, prepared, warp, s, 0u, 0.0f).radiance;
                  }};
}

} // namespace gt::render
