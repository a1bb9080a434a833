#pragma once
// The thesis's method (thesis, sections 4.1-4.3): a perceptual point set, built once per display
// (size and pixels per degree) and cached on disk, shifted to the view's gaze; `point_sample`
// traces R rays in every point's disc, `interpolate` rebuilds every pixel from the k nearest
// points (nearest neighbour, Modified Shepard, radial basis functions). What the interpolation
// settings need is built on the CPU when they change: the per-pixel k-NN table, RBF's per-pixel
// weights or per-point inverses.
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <utility>

#include <glm/glm.hpp>

#include "edge_rays/edge_rays.hpp"
#include "foveation/gpu_point_set.hpp"
#include "foveation/neighbour_index.hpp"
#include "foveation/point_set.hpp"
#include "foveation_method.hpp"
#include "interpolate/interpolate.hpp"
#include "point_denoise/point_denoise.hpp"
#include "point_sample/point_sample.hpp"
#include "rbf_solve/rbf_solve.hpp"
#include "taa/taa.hpp"

namespace gt::render {

// The one-off cost of something built on the CPU for the interpolation settings.
struct Prepared {
    double ms = 0.0;
    double mb = 0.0;
};

// How far Modified Shepard's sites move each frame, as a share of their spacing p
// (site_jitter.glsl): with the camera moving, and with it still and TAA pooling the frames by
// their support (taa.glsl). eval, builtin:market and the classroom, fove, 4 rays per point:
// 0.8 against 0.5 lowers flip_ecc beyond 20 deg by 8-22 % on a still view, while with the
// camera moving it raised the periphery's flicker above the one-ray reference's (0.60 % against
// 0.59 % of the pixels beyond 20 deg changing by more than 10/255).
inline constexpr float kSiteJitterMoving = 0.5f;
inline constexpr float kSiteJitterStill = 0.8f;

struct PointSetSettings {
    uint32_t raysPerPoint = 32;
    passes::InterpolateSettings interpolation;
    // For views with a lens (the HMD path): lay the set on the panel, around the panel point
    // that shows the gaze, and trace each ray where the lens sends its panel position
    // (engine/display/display_space.hpp); the result is the panel's image.
    bool displaySpace = false;
    // Geometric LOD (Guenter et al. 2012, 6): points whose spacing is large trace coarser
    // refinements of the scene's subdivision cages (point_sample.comp); a scene without cages is
    // unaffected.
    bool lod = true;
    // Blend the interpolation in display-referred space at the view's exposure
    // (InterpolateSettings::displayExposure); false: linear radiance, as the thesis.
    bool displayReferred = true;
    // Every frame, rotate each point's rays inside its disc (point_sample.comp) and, for
    // Modified Shepard, move its site within half its spacing
    // (site_jitter.glsl), so TAA accumulates new rays and new cell boundaries on a still view;
    // false: the same rays at the same sites every frame, as the thesis.
    bool jitter = true;
    // Rays within 0.6 px of each point's site (point_sample.comp, kRayDiscMaxPx); false:
    // anywhere in the point's disc of radius p, as the thesis.
    bool pixelRays = true;
    // Dispatch only the chunks of the set that can land on screen (passes::PointDispatch) while
    // the sites stay put (no Modified Shepard site moves this frame); false: a thread for every
    // point of the canvas set. With moving sites the whole set is dispatched: there the chunks
    // changed RendererTest.PoolingFramesBySupportBeatsTheirPlainMean's 9-frame result although
    // every point within reach of the screen is traced (PointChunks tests), cause not yet found.
    // Chunks also only where less than kChunkedShare of the set lands on screen
    // (PointSetMethod::dispatchFor).
    bool onScreenChunks = true;
    // In a scene that moves, a ray of its own for each pixel on a moving edge
    // (passes::EdgeRaysPass); false: those pixels keep the reconstruction's blend.
    bool edgeRays = true;
    // What each point's rays compute: the direct integrator or the path tracer
    // (trace::IntegratorSettings). The edge rays stay with the direct integrator.
    trace::IntegratorSettings integrator{};
    // Paths per point by eccentricity: the points within foveaDeg of the gaze trace this many
    // rays each instead of raysPerPoint (0: the same), as Mohanto et al. 2024 spend more
    // samples per pixel in the fovea.
    uint32_t foveaRaysPerPoint = 0;
    double foveaDeg = 5.0;
    // With the path integrator, Modified Shepard blends with q = 1 and no colour guidance,
    // whatever `interpolation` says (noisySampleWeights); false: `interpolation` as given.
    bool noisySampleWeights = true;
};

// The interpolation for samples that each carry their own noise (a path tracer's): q = 1 and no
// colour guidance. q = 2 leans on the nearest sample, and colour guidance takes a noisy
// sample's deviation for an edge and keeps it; both keep one sample's noise where q = 1
// averages the k neighbours (docs/path-tracing.md, "Reconstructing noisy samples").
void useNoisySampleWeights(passes::InterpolateSettings& s);

inline constexpr double kChunkedShare = 0.5;

// The thesis's reconstruction exactly as the thesis did it, for comparison: linear radiance,
// Modified Shepard with q = 1 and no guidance, the same rays every frame, and a fixed TAA blend.
// The defaults instead blend display-referred, weigh neighbours by depth and colour, use q = 2,
// rotate the rays every frame and let TAA average a still view (README, "Reconstruction").
void useThesisReconstruction(PointSetSettings& settings, passes::TaaSettings& taa);

class PointSetMethod final : public FoveationMethod {
public:
    // Loads (or generates and caches in `cacheDir`) the point set for `params` and builds its
    // neighbour index. Views must have the size of params.display.
    PointSetMethod(const MethodContext& mc, const foveation::PointSetParams& params,
                   const std::filesystem::path& cacheDir);
    // The same from a set already loaded or generated (`pointSetMs` it took), e.g. off the frame
    // thread: builds its neighbour index and GPU buffers here.
    PointSetMethod(const MethodContext& mc, foveation::PointSet points, double pointSetMs);
    ~PointSetMethod() override;

    [[nodiscard]] std::string_view name() const override { return "foveated"; }
    [[nodiscard]] MethodImage addRadiance(rg::RenderGraph& graph, const View& view) override;
    [[nodiscard]] uint64_t rays(const View& view) const override;
    [[nodiscard]] std::optional<WarmUp> warmUp(const View& view) override;
    [[nodiscard]] bool rendersPanel(const View& view) const override;
    // The panel point that shows `view`'s gaze when the set is laid on the panel, else the gaze.
    [[nodiscard]] glm::vec2 sampledGaze(const View& view) const;
    void frameSubmitted() override { ++mFrame; }
    [[nodiscard]] bool gazeDependent() const override { return true; }
    // The path integrator's samples, when `view`'s denoiser is placed on the points.
    [[nodiscard]] bool denoisesPoints(const View& view) const override;

    PointSetSettings settings;

    [[nodiscard]] const foveation::PointSet& pointSet() const noexcept { return mPoints; }
    // Points traced with the set shifted to `gaze` (on screen plus the sampling margin).
    [[nodiscard]] std::size_t pointsSampled(glm::vec2 gaze) const;
    // settings.foveaRaysPerPoint's radius on this set's display, in pixels (0: off).
    [[nodiscard]] float foveaRadiusPx() const;
    // Whether TAA may weigh a still view's frames by how near their samples fell to each pixel
    // (MethodImage::support). That keeps, per pixel, the few frames that sampled it closely: the
    // sharpest estimate of a sample that is exact, as the direct integrator's are. A path
    // tracer's samples each carry their own noise, and those few frames are as noisy as one:
    // its frames count equally.
    [[nodiscard]] bool supportsTaa() const {
        return settings.integrator.integrator != trace::Integrator::Path;
    }
    // settings.interpolation, with useNoisySampleWeights for path-traced samples
    // (settings.noisySampleWeights).
    [[nodiscard]] passes::InterpolateSettings interpolation() const;
    // Points traced within `radius` pixels of `view`'s gaze (on screen plus the margin).
    [[nodiscard]] std::size_t pointsWithin(const View& view, float radius) const;
    [[nodiscard]] double pointSetMs() const noexcept { return mPointSetMs; }
    [[nodiscard]] double neighbourIndexMs() const noexcept { return mNeighbourMs; }
    [[nodiscard]] double neighbourIndexMb() const noexcept { return mNeighbourMb; }
    // Whether the neighbour index went to the GPU: only once a pass read it (not for Modified
    // Shepard through the table).
    [[nodiscard]] bool neighbourIndexOnGpu() const noexcept { return mGpuPoints.hasIndex(); }
    // For the RBF settings of the last RBF frame, and the k of the last frame that used the
    // per-pixel k-NN table.
    [[nodiscard]] Prepared rbfPrepared() const noexcept { return mRbfPrepared; }
    [[nodiscard]] Prepared knnTablePrepared() const noexcept { return mKnnTablePrepared; }

private:
    struct TimedSet {
        foveation::PointSet set;
        double ms = 0.0;
    };
    PointSetMethod(const MethodContext& mc, TimedSet loaded);
    struct LastFrame {
        shaders::trace::CameraPush camera;
        glm::vec2 gaze; // sampledGaze's
    };
    struct PointDenoising {
        passes::PointDenoiseSettings settings;
        std::optional<passes::PointDenoiseHistory> history;
    };
    passes::InterpolateInputs tableInputs(const passes::InterpolateSettings& s);
    const foveation::GpuRbfInverse& inverseFor(const passes::InterpolateSettings& s);
    passes::InterpolatedImage
    addImage(rg::RenderGraph& graph, const shaders::trace::CameraPush& camera, glm::vec2 gaze,
             uint32_t rays, uint32_t lanes, const passes::InterpolateInputs& prepared,
             const std::optional<passes::PanelWarp>& warp, passes::InterpolateSettings s,
             uint32_t frame, float siteJitter,
             const std::optional<PointDenoising>& denoise = std::nullopt);
    // The point denoiser's settings for `view` (denoisesPoints), else none; its temporal
    // history from `last`, the view's previous frame (none: its first).
    [[nodiscard]] std::optional<PointDenoising>
    pointDenoiseFor(const View& view, const std::optional<LastFrame>& last) const;
    [[nodiscard]] std::optional<passes::PanelWarp> warpFor(const View& view) const;
    // Chunks (settings.onScreenChunks) or the whole set, for this frame's gaze and site moves.
    [[nodiscard]] passes::PointDispatch dispatchFor(glm::vec2 gaze, float siteJitter) const;

    MethodContext mMc;
    uint32_t mFrame = 0; // frames submitted: the ray-position rotation of the next one
    std::map<std::string, LastFrame> mLastFrame; // per view, its last frame's camera and gaze
    foveation::PointSet mPoints;
    foveation::NeighbourIndex mNeighbours;
    foveation::GpuPointSet mGpuPoints;
    passes::PointSamplePass mPointSample;
    passes::InterpolatePass mInterpolate;
    passes::RbfSolvePass mRbfSolve;
    passes::PointDenoisePass mPointDenoise;
    std::unique_ptr<passes::MotionViewPass> mMotionView; // --view motion, built on first use
    std::unique_ptr<passes::EdgeRaysPass> mEdgeRays;     // a scene that moves, built on first use
    std::optional<foveation::GpuRbfInverse> mRbfInverse;
    std::optional<foveation::GpuPixelKnnTable> mKnnTable;
    std::optional<foveation::GpuRbfPixelWeights> mRbfPixelWeights;
    Prepared mRbfPrepared, mKnnTablePrepared;
    double mPointSetMs = 0.0, mNeighbourMs = 0.0, mNeighbourMb = 0.0;
    mutable std::optional<std::pair<glm::vec2, std::size_t>> mSampledMemo; // offset -> points
    // (offset, radius) -> the sampled points within the fovea's radius
    mutable std::optional<std::pair<glm::vec3, std::size_t>> mFoveaMemo;
    // Pipeline variants (interpolation, reads the table, point_sample lanes) that have run.
    std::set<std::tuple<passes::Interpolation, bool, uint32_t>> mWarm;
};

} // namespace gt::render
