#include "eval_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <numbers>
#include <optional>
#include <span>
#include <sstream>
#include <thread>

#include "atomic_write.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "eval_plots.hpp"
#include "eval_progress.hpp"
#include "foveation/contrast_sensitivity.hpp"
#include "foveation/gaze_trace.hpp"
#include "foveation/neighbour_index.hpp"
#include "frame_loop.hpp"
#include "full_resolution.hpp"
#include "gaze_view.hpp"
#include "layers_command.hpp"
#include "match_search.hpp"
#include "method_choice.hpp"
#include "option_parsing.hpp"
#include "output_target.hpp"
#include "point_set_method.hpp"
#include "quality/eccentricity_bands.hpp"
#include "quality/flip.hpp"
#include "quality/image_metrics.hpp"
#include "quality/resample.hpp"
#include "renderer.hpp"
#include "scene/camera_path.hpp"
#include "scene/image_io.hpp"
#include "stereo_rig.hpp"
#include "view_args.hpp"

namespace gt::app {

namespace {

using quality::kBandNames;
using quality::kBands;
using quality::RgbaImage;
using quality::ScalarMap;

constexpr uint32_t kSeed = 7; // the reference's and the baselines' ray seed

// Where the eye is and what it resolves: the display geometry every measure is taken in.
struct Geometry {
    foveation::DisplayProfile display; // the (window) profile: size and viewing distance
    std::optional<trace::FrustumTangents> frustum; // --hmd: the left eye's off-axis frustum
    uint32_t width = 0, height = 0;
    glm::vec2 gaze{};
    double ppd = 0.0; // at the display's centre
    std::vector<uint8_t> bands;
};

// Views rendered and read back as pictures, one frame or a sequence through the frame loop.
class Shooter {
public:
    Shooter(render::Renderer& r, EvalProgress& p)
        : mRenderer(r), mReadback(r.context()), mProgress(p) {}
    RgbaImage shot(const render::View& v, render::FoveationMethod& m, uint64_t* rays = nullptr) {
        RgbaImage img;
        sequence(
            1, [&](const FrameTick&) { return v; }, m,
            [&](const FrameTick&, RgbaImage shot, uint64_t r) {
                img = std::move(shot);
                if (rays) *rays = r;
            });
        return img;
    }
    // `frames` frames, frame t of the view `view(t)` through `m` (at the scene's exposure),
    // each handed to `frame` as a picture with the primary rays it traced.
    // The scene time of every frame of a sequence unless it says otherwise: eval's pictures
    // are of one instant of an animated scene (--time).
    void holdSceneTime(double seconds) { mSceneSeconds = seconds; }
    void sequence(uint32_t frames, const std::function<render::View(const FrameTick&)>& view,
                  render::FoveationMethod& m,
                  const std::function<void(const FrameTick&, RgbaImage, uint64_t)>& frame,
                  const std::function<double(const FrameTick&)>& sceneTime = {}) {
        // The gaze source is the view's own gaze (a fixed point, or a pursuit trace's sample).
        mGpuMs.clear();
        render::View current;
        FrameStages<glm::vec2> stages;
        stages.gaze = [&](const FrameTick& t) {
            current = view(t);
            return current.gaze;
        };
        stages.views = [&](const FrameTick&, const glm::vec2&) {
            current.method = &m;
            current.exposure = mRenderer.scene().exposure;
            return std::vector<render::View>{current};
        };
        stages.targets = [&](const FrameTick&, std::span<const render::View>) {
            return std::vector<render::OutputTarget*>{&mReadback};
        };
        stages.done = [&](const FrameTick& t, const glm::vec2&, std::span<const render::View> v,
                          const render::FrameResult& f) {
            RgbaImage img{v[0].width, v[0].height, mReadback.takePixels()};
            mGpuMs.push_back(renderedGpuMs(f));
            mProgress.frame(v[0].name);
            frame(t, std::move(img), f.views.front().rays);
            return true;
        };
        stages.sceneTime =
            sceneTime ? sceneTime : [this](const FrameTick&) { return mSceneSeconds; };
        (void)runFrameLoop(mRenderer, FrameClock(), frames, stages);
    }
    // The GPU time of each frame of the last sequence, the readback to the host left out.
    [[nodiscard]] const std::vector<double>& gpuMs() const noexcept { return mGpuMs; }

private:
    static double renderedGpuMs(const render::FrameResult& f) {
        if (!f.timings) {
            return 0.0;
        }
        double readback = 0.0;
        for (const auto& p : f.timings->passes) {
            readback += p.name.starts_with("readback.") ? p.gpuMs : 0.0;
        }
        return f.timings->gpuMs - readback;
    }

    std::vector<double> mGpuMs;
    double mSceneSeconds = 0.0;
    render::Renderer& mRenderer;
    render::ReadbackTarget mReadback;
    EvalProgress& mProgress;
};

nlohmann::json bandsJson(const std::array<double, kBands>& v) {
    nlohmann::json j = nlohmann::json::object();
    for (std::size_t b = 0; b < kBands; ++b) {
        j[std::string(kBandNames[b])] = v[b];
    }
    return j;
}

// Every still-picture measure of `img` against `ref`, per band.
struct Scores { // NOLINT(bugprone-exception-escape): nlohmann::json's members may allocate
    nlohmann::json json;
    ScalarMap flip;
    std::array<double, kBands> flipBands{}, flipEcc{};
};

Scores score(const RgbaImage& img, const RgbaImage& ref, const Geometry& g,
             const std::vector<uint8_t>& bleedMask) {
    Scores s;
    s.flip = quality::flipErrorMap(ref, img, g.ppd);
    s.flipBands = quality::meanPerBand(s.flip, g.bands);
    // flip_ecc: band b as the eye resolves it at its inner eccentricity e. Its acuity there is
    // fc(e) / fc(0) of the fovea's, so a pixel spans that much less of what it can resolve:
    // FLIP's observer sees the display at ppd * fc(0) / fc(e) pixels per degree (as if from
    // farther away), and detail finer than the eye resolves there is filtered out.
    s.flipEcc[0] = s.flipBands[0];
    for (std::size_t b = 1; b < kBands; ++b) {
        const double ppd = g.ppd / quality::acuityFalloff(quality::kBandStartDeg[b]);
        s.flipEcc[b] = quality::meanPerBand(quality::flipErrorMap(ref, img, ppd), g.bands)[b];
    }
    const auto mse = quality::meanPerBand(quality::squaredErrorMap(ref, img), g.bands);
    const ScalarMap absErr = quality::absoluteErrorMap(ref, img);
    const auto mad = quality::meanPerBand(absErr, g.bands);
    const auto ssim = quality::meanPerBand(quality::ssimMap(ref, img), g.bands);
    nlohmann::json bands = nlohmann::json::object();
    for (std::size_t b = 0; b < kBands; ++b) {
        bands[std::string(kBandNames[b])] = {{"flip", s.flipBands[b]},
                                             {"flip_ecc", s.flipEcc[b]},
                                             {"psnr_db", quality::psnrDb(mse[b])},
                                             {"ssim", ssim[b]},
                                             {"mad", mad[b]}};
    }
    double bleed = 0.0;
    std::size_t n = 0;
    for (std::size_t p = 0; p < bleedMask.size(); ++p) {
        if (bleedMask[p]) {
            bleed += absErr[p];
            ++n;
        }
    }
    double flipMean = 0.0;
    for (const float v : s.flip) {
        flipMean += v;
    }
    s.json = {{"bands", bands},
              {"flip_mean", flipMean / static_cast<double>(s.flip.size())},
              {"bleed_mad", n ? bleed / static_cast<double>(n) : 0.0},
              {"bleed_pixels", n}};
    return s;
}

// The direction of the ray through the centre of pixel (x, y) of a w x h image (trace.glsl's
// cameraRay for a symmetric frustum).
glm::vec3 pixelRay(const shaders::trace::CameraPush& c, uint32_t x, uint32_t y, uint32_t w,
                   uint32_t h) {
    const float sx = (2.0f * (static_cast<float>(x) + 0.5f) / static_cast<float>(w) - 1.0f) *
                     c.origin.w * c.forward.w;
    const float sy =
        (1.0f - 2.0f * (static_cast<float>(y) + 0.5f) / static_cast<float>(h)) * c.origin.w;
    return glm::normalize(glm::vec3(c.forward) + sx * glm::vec3(c.right) + sy * glm::vec3(c.up));
}

// First-hit distance per pixel centre (infinity for the sky), on the CPU from the renderer's
// BVH: what a moving camera's frames are reprojected with.
std::vector<float> depthMap(const render::Renderer& r, const scene::Camera& cam, uint32_t w,
                            uint32_t h) {
    const auto c = trace::cameraPush(cam, static_cast<float>(w) / static_cast<float>(h));
    std::vector<float> depth(static_cast<std::size_t>(w) * h);
    auto rows = [&](uint32_t y0, uint32_t y1) {
        for (uint32_t y = y0; y < y1; ++y) {
            for (uint32_t x = 0; x < w; ++x) {
                depth[static_cast<std::size_t>(y) * w + x] =
                    r.bvh().intersect({glm::vec3(c.origin), pixelRay(c, x, y, w, h)}).t;
            }
        }
    };
    const uint32_t threads = std::max(1u, std::min(4u, std::thread::hardware_concurrency()));
    std::vector<std::jthread> pool;
    for (uint32_t t = 0; t < threads; ++t) {
        pool.emplace_back(rows, h * t / threads, h * (t + 1) / threads);
    }
    return depth;
}

// Per band, the share (%) of pixels of `cur` that differ by more than 10/255 in some channel
// from `prev` reprojected into `cur`'s camera (pixels seen in both frames only), and the mean
// absolute change.
struct Change {
    std::array<double, kBands> share{}, mean{};
};

// Adds pixels' changes per band; change() gives the shares and means.
class ChangeTally {
public:
    // `diff` per colour channel, in 1/255.
    void add(uint8_t band, const std::array<float, 3>& diff) {
        const float largest = std::max({diff[0], diff[1], diff[2]});
        mChanged[band] += largest > 10.0f ? 1 : 0;
        mSum[band] += (diff[0] + diff[1] + diff[2]) / 3.0;
        ++mCount[band];
    }
    [[nodiscard]] Change change() const {
        Change out;
        for (std::size_t b = 0; b < kBands; ++b) {
            const auto n = static_cast<double>(mCount[b]);
            out.share[b] = mCount[b] ? 100.0 * static_cast<double>(mChanged[b]) / n : 0.0;
            out.mean[b] = mCount[b] ? mSum[b] / n : 0.0;
        }
        return out;
    }

private:
    std::array<uint64_t, kBands> mChanged{}, mCount{};
    std::array<double, kBands> mSum{};
};

Change reprojectedChange(const RgbaImage& prev, const RgbaImage& cur, const scene::Camera& pc,
                         const scene::Camera& cc, const std::vector<float>& prevDepth,
                         const std::vector<float>& curDepth, const std::vector<uint8_t>& bands) {
    const uint32_t w = cur.width, h = cur.height;
    const float aspect = static_cast<float>(w) / static_cast<float>(h);
    const auto c = trace::cameraPush(cc, aspect), p = trace::cameraPush(pc, aspect);
    ChangeTally tally;
    for (uint32_t y = 0; y < h; ++y) {
        for (uint32_t x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * w + x;
            const glm::vec3 dir = pixelRay(c, x, y, w, h);
            const bool sky = !(curDepth[i] < 1e30f);
            const glm::vec3 d =
                sky ? dir : glm::vec3(c.origin) + curDepth[i] * dir - glm::vec3(p.origin);
            const float z = glm::dot(d, glm::vec3(p.forward));
            if (z <= 1e-6f) {
                continue;
            }
            const float u = glm::dot(d, glm::vec3(p.right)) / z / (p.origin.w * p.forward.w);
            const float v = glm::dot(d, glm::vec3(p.up)) / z / p.origin.w;
            const float fx = (u + 1.0f) * 0.5f * static_cast<float>(w) - 0.5f;
            const float fy = (1.0f - v) * 0.5f * static_cast<float>(h) - 0.5f;
            const auto x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
            if (x0 < 0 || y0 < 0 || x0 + 1 >= static_cast<int>(w) ||
                y0 + 1 >= static_cast<int>(h)) {
                continue;
            }
            // Seen in both frames: the previous frame's surface at the expected distance.
            const auto nearest = static_cast<std::size_t>(std::lround(fy)) * w +
                                 static_cast<std::size_t>(std::lround(fx));
            const float expected = sky ? 1e31f : glm::length(d);
            const bool prevSky = !(prevDepth[nearest] < 1e30f);
            if (sky != prevSky ||
                (!sky && std::abs(prevDepth[nearest] - expected) > 0.02f * expected)) {
                continue;
            }
            const float tx = fx - static_cast<float>(x0), ty = fy - static_cast<float>(y0);
            std::array<float, 3> diff{};
            for (int ch = 0; ch < 3; ++ch) {
                auto at = [&](int xx, int yy) {
                    return static_cast<float>(prev.at(
                        static_cast<std::size_t>(yy) * w + static_cast<std::size_t>(xx), ch));
                };
                const float pv = (1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x0 + 1, y0)) +
                                 ty * ((1 - tx) * at(x0, y0 + 1) + tx * at(x0 + 1, y0 + 1));
                diff[static_cast<std::size_t>(ch)] =
                    std::abs(pv - static_cast<float>(cur.at(i, ch)));
            }
            tally.add(bands[i], diff);
        }
    }
    return tally.change();
}

// The same for a still camera (no reprojection).
Change stillChange(const RgbaImage& prev, const RgbaImage& cur, const std::vector<uint8_t>& bands) {
    ChangeTally tally;
    for (std::size_t i = 0; i < cur.count(); ++i) {
        std::array<float, 3> diff{};
        for (int ch = 0; ch < 3; ++ch) {
            diff[static_cast<std::size_t>(ch)] =
                std::abs(static_cast<float>(prev.at(i, ch)) - static_cast<float>(cur.at(i, ch)));
        }
        tally.add(bands[i], diff);
    }
    return tally.change();
}

nlohmann::json changeJson(const std::vector<Change>& steps) {
    std::array<double, kBands> share{}, mean{};
    for (const Change& c : steps) {
        for (std::size_t b = 0; b < kBands; ++b) {
            share[b] += c.share[b] / static_cast<double>(steps.size());
            mean[b] += c.mean[b] / static_cast<double>(steps.size());
        }
    }
    return {{"changed_percent", bandsJson(share)}, {"mean_abs_change", bandsJson(mean)}};
}

void writePng(const std::filesystem::path& path, const RgbaImage& img) {
    image::writePngAtomic(path, img.width, img.height, img.pixels);
}

// The uniform render at the resolution that spends `rays` with `rpp` rays per pixel, at the
// display's aspect.
std::pair<uint32_t, uint32_t> uniformSize(uint64_t rays, uint32_t rpp, uint32_t w, uint32_t h) {
    const double pixels = static_cast<double>(rays) / rpp;
    const double uw = std::sqrt(pixels * w / h);
    return {std::max(1u, static_cast<uint32_t>(std::lround(uw))),
            std::max(1u, static_cast<uint32_t>(std::lround(uw * h / w)))};
}

void checkEvalOptions(const EvalOptions& o) {
    const std::vector<std::string> profiles = displayProfileNames();
    if (!o.hmd.empty() && (o.width || o.height)) {
        throw ArgumentError("--width/--height: --hmd " + o.hmd + " renders its own eye size");
    }
    if (std::find(profiles.begin(), profiles.end(), o.profile) == profiles.end()) {
        throw ArgumentError("--profile: unknown display profile '" + o.profile + "'");
    }
    if (o.k == 0 || o.k > foveation::NeighbourIndex::kMaxNeighbours) {
        throw ArgumentError("--k must be 1..20");
    }
    if (o.blend != "display" && o.blend != "linear") {
        throw ArgumentError("--blend: expected display or linear, got '" + o.blend + "'");
    }
    if (!(o.edgeTolerance >= 0.0) || o.edgeTolerance > 100.0) {
        throw ArgumentError("--edge-tolerance: expected 0 (off) .. 100");
    }
    if (o.baseline != "uniform" && o.baseline != "none") {
        throw ArgumentError("--baseline: expected uniform or none, got '" + o.baseline + "'");
    }
    if (o.method != "points" && o.method != "layers") {
        throw ArgumentError("--method: expected points or layers, got '" + o.method + "'");
    }
    if (o.method == "layers" && o.integrator.integrator != "direct") {
        throw ArgumentError("--integrator " + o.integrator.integrator +
                            ": --method points only (layers trace the direct integrator)");
    }
    (void)parseIntegrator(o.integrator);
    if (o.method == "layers" && o.sweep) {
        throw ArgumentError("--sweep: point-set scales; not with --method layers");
    }
    if (!o.match.empty() && o.match != "uniform" && o.match != "full") {
        throw ArgumentError("--match: expected uniform or full, got '" + o.match + "'");
    }
    if (o.matchDoublings && o.match != "uniform") {
        throw ArgumentError("--match-doublings: with --match uniform only");
    }
}

// The options checked; whether --reconstruction is the thesis's.
bool checkedThesis(const EvalOptions& o) {
    checkEvalOptions(o);
    return (parseReconstruction(o.reconstruction) == render::Reconstruction::Thesis);
}

// A headset's left eye: its image, its frustum, the point set of its field of view, and by
// default the gaze straight ahead (where its optical axis meets the image), as the scale
// bench looks. The eye sits at the head's position: one eye needs no inter-pupillary offset.
Geometry hmdGeometry(const EvalOptions& o) {
    const display::HmdProfile hmd = hmdProfile(o.hmd);
    const display::EyeTangents t = display::eyeTangents(hmd, 0);
    Geometry g;
    g.display = hmd.pointSetProfile;
    g.frustum = trace::FrustumTangents{t.left, t.right, t.up, t.down};
    g.width = hmd.eyeWidth;
    g.height = hmd.eyeHeight;
    g.gaze = o.gaze.empty()
                 ? render::pixelOfDirection(glm::vec3(0.0f, 0.0f, 1.0f), t, g.width, g.height)
                 : parseGaze(o.gaze, g.width, g.height);
    return g;
}

Geometry evalGeometry(const EvalOptions& o) {
    Geometry g;
    if (!o.hmd.empty()) {
        g = hmdGeometry(o);
    } else {
        const foveation::DisplayProfile screen = displayProfile(o.profile);
        g.display = (o.width || o.height)
                        ? foveation::windowProfile(screen, o.width ? o.width : screen.width,
                                                   o.height ? o.height : screen.height)
                        : screen;
        g.width = g.display.width;
        g.height = g.display.height;
        g.gaze = parseGaze(o.gaze, g.width, g.height);
    }
    g.ppd = quality::pixelsPerDegree(g.display.width, g.display.viewingDistance);
    g.bands = quality::bandMap(g.display, g.width, g.height, g.gaze);
    return g;
}

// The inputs that can be wrong, loaded and checked before any rendering.
struct EvalInputs {
    std::optional<scene::CameraPath> path;
    std::optional<foveation::GazeTrace> pursuit;
    std::optional<RgbaImage> reference;
};

EvalInputs evalInputs(const EvalOptions& o, const Geometry& g) {
    EvalInputs in;
    if (!o.cameraPath.empty()) {
        in.path = scene::CameraPath::load(o.cameraPath);
    }
    if (!o.pursuit.empty()) {
        in.pursuit = foveation::GazeTrace::load(o.pursuit);
        if (in.pursuit->units() != foveation::GazeUnits::Pixels) {
            throw LoadError(o.pursuit + ": eval needs a gaze trace in pixels");
        }
    }
    if (!o.reference.empty()) {
        // image::readPng reads through the shared input rule (regular files of bounded size).
        const image::DecodedImage d = image::readPng(o.reference);
        if (d.width != g.width || d.height != g.height) {
            throw LoadError(o.reference + ": the reference is " + std::to_string(d.width) + "x" +
                            std::to_string(d.height) + ", the view " + std::to_string(g.width) +
                            "x" + std::to_string(g.height));
        }
        in.reference = RgbaImage{d.width, d.height, d.rgba};
    }
    return in;
}

// The uniform baselines at some rays: the low-resolution render upscaled both ways, and the
// full-resolution frame with the same total rays.
struct Baselines {
    RgbaImage bilinear, bicubic, fullRes;
    uint32_t uw = 0, uh = 0, fullSpp = 0;
};

// What --match compares: the foveated frame's, or a uniform candidate's, rays, settled GPU
// time and flip_ecc per band.
struct MatchEntry {
    uint32_t width = 0, height = 0, raysPerPixel = 0; // the render's (a candidate's)
    uint64_t rays = 0;
    double gpuMs = 0.0;
    std::array<double, kBands> flipEcc{};
    bool matches = false;
};

nlohmann::json matchEntryJson(const MatchEntry& e) {
    return {
        {"size", {e.width, e.height}}, {"rays_per_pixel", e.raysPerPixel}, {"rays", e.rays},
        {"gpu_ms_median", e.gpuMs},    {"flip_ecc", bandsJson(e.flipEcc)}, {"matches", e.matches}};
}

// The largest of a candidate's per-band flip_ecc over the target's: at most 1 where it matches.
double worstBandRatio(const MatchEntry& c, const MatchEntry& target) {
    double worst = 0.0;
    for (std::size_t b = 0; b < kBands; ++b) {
        worst = std::max(worst, c.flipEcc[b] / std::max(target.flipEcc[b], 1e-12));
    }
    return worst;
}

// A settled frame's GPU time: the median over a sequence's frames after the first (which
// compiles pipelines and builds tables). `pairs`: of the means of consecutive frames, for
// layers at half rate, whose frames alternate between two costs.
double settledGpuMs(const std::vector<double>& ms, bool pairs) {
    std::vector<double> v;
    const std::size_t first = ms.size() > 1 ? 1 : 0;
    for (std::size_t i = first; i < ms.size(); ++i) {
        if (!pairs) {
            v.push_back(ms[i]);
        } else if (i + 1 < ms.size()) {
            v.push_back(0.5 * (ms[i] + ms[i + 1]));
        }
    }
    if (v.empty()) {
        return ms.empty() ? 0.0 : ms.back();
    }
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// One eval run: the renderer, the view every measure shares, the reference, and the frames
// and sequences of each method against it.
class EvalRun {
public:
    explicit EvalRun(const EvalOptions& o);
    nlohmann::json run();

private:
    std::unique_ptr<render::PointSetMethod> makeFoveated(double scale);
    std::unique_ptr<render::EccentricityLayers> makeLayers();
    RgbaImage foveatedFrame(render::FoveationMethod& m, const std::string& name, uint64_t& rays);
    Baselines baselines(uint64_t rays);
    nlohmann::json summaryHead();
    void stillFrame(nlohmann::json& summary);
    nlohmann::json stillSequence();
    nlohmann::json movingSequence();
    nlohmann::json pursuitSequence();
    nlohmann::json pursuitOf(render::FoveationMethod& method, const char* name);
    void foveaCheck(nlohmann::json& summary);
    // The base view at w x h, its gaze scaled with it: the denoiser keeps the fovea of a
    // smaller uniform frame where the eye is, not at the full frame's pixel coordinates.
    [[nodiscard]] render::View viewAt(uint32_t w, uint32_t h) const {
        render::View v = mBase;
        const glm::vec2 scale(static_cast<float>(w) / static_cast<float>(mBase.width),
                              static_cast<float>(h) / static_cast<float>(mBase.height));
        v.gaze = (mBase.gaze + 0.5f) * scale - 0.5f; // pixel centres at integers
        v.width = w;
        v.height = h;
        return v;
    }
    [[nodiscard]] bool pathTraced() const noexcept {
        return mIntegrator.integrator != trace::Integrator::Direct;
    }
    nlohmann::json animatedSequence();
    void sweep(nlohmann::json& summary);
    MatchEntry matchCandidate(uint32_t width, uint32_t height, uint32_t raysPerPixel,
                              RgbaImage& picture);
    nlohmann::json timedInTurns(const MatchEntry& match);
    void match(nlohmann::json& summary);
    // Scores of a frame against the reference.
    Scores scored(const RgbaImage& img) const { return score(img, mRef, mGeometry, mBleedMask); }

    const EvalOptions& mOptions;
    bool mThesis; // --reconstruction thesis
    Geometry mGeometry;
    EvalInputs mInputs;
    io::StagedFolder mFolder;   // --out, replaced by the run's files only when it succeeds
    std::filesystem::path mOut; // where the files go meanwhile: the staged folder
    std::optional<render::Renderer> mRenderer;
    std::optional<EvalProgress> mProgress;
    std::optional<Shooter> mShooter;
    scene::Camera mCamera;
    render::View mBase;
    RgbaImage mRef;
    std::vector<uint8_t> mBleedMask;
    std::unique_ptr<render::FoveationMethod> mFoveated;
    MatchEntry mTarget; // the foveated still frame, for --match
    render::IntegratorSettings mIntegrator;
};

EvalRun::EvalRun(const EvalOptions& o)
    : mOptions(o), mThesis(checkedThesis(o)), mGeometry(evalGeometry(o)),
      mInputs(evalInputs(o, mGeometry)), mFolder(o.out), mOut(mFolder.temp()),
      mIntegrator(parseIntegrator(o.integrator)) {
    const std::optional<CameraArg> cameraArg = parseCamera(o.camera);
    mRenderer.emplace(render::RendererOptions{.scene = o.scene,
                                              .validate = o.validate,
                                              .framesInFlight = 1,
                                              .deviceOverride = deviceRequest(),
                                              .sceneLoad = gltfLoadOptions(),
                                              .animation = o.animation});
    mProgress.emplace(evalFrameCount(o, mInputs.reference.has_value(),
                                     mInputs.pursuit ? mInputs.pursuit->samples().size() : 0));
    mShooter.emplace(*mRenderer, *mProgress);
    mShooter->holdSceneTime(o.time);
    mRenderer->setSceneTime(o.time);
    mCamera = mRenderer->sceneCamera();
    if (cameraArg) {
        mCamera = cameraArg->camera(mCamera.yfov);
    }
    mBase.camera = mCamera;
    mBase.frustum = mGeometry.frustum;
    mBase.width = mGeometry.width;
    mBase.height = mGeometry.height;
    mBase.gaze = mGeometry.gaze;
    mBase.post.taa = false;
    mBase.post.taaSettings.stillClipGamma = static_cast<float>(o.stillClipGamma);
    mBase.post.taaSettings.eccentricRadius = static_cast<float>(o.eccentricRadius);
    if (mThesis) {
        render::PointSetSettings unused;
        render::useThesisReconstruction(unused, mBase.post.taaSettings);
    }
    // The reference: many stratified rays per pixel, no TAA.
    if (mInputs.reference) {
        mRef = std::move(*mInputs.reference);
    } else {
        render::FullResolution reference(mRenderer->methodContext(),
                                         {o.referenceSpp, kSeed, mIntegrator});
        render::View v = mBase;
        v.name = "reference";
        mRef = mShooter->shot(v, reference);
        writePng(mOut / "reference.png", mRef);
    }
    // Every frame after the ground truth: the foveated, uniform and one-ray frames alike.
    mBase.post.denoise = parseDenoise(o.integrator);
    mBleedMask = quality::darkNearBrightMask(mRef);
}

std::unique_ptr<render::PointSetMethod> EvalRun::makeFoveated(double scale) {
    const EvalOptions& o = mOptions;
    foveation::PointSetParams params;
    params.display = mGeometry.display;
    params.scale = scale;
    auto m = makePointSetMethod(*mRenderer, params, o.cacheDir);
    m->settings.raysPerPoint = o.raysPerPoint;
    m->settings.interpolation.method = interpolationOf(o.interp, o.k, "").method;
    m->settings.interpolation.k = o.k;
    m->settings.lod = o.lod;
    m->settings.displayReferred = o.blend == "display";
    m->settings.interpolation.edgeTolerance = static_cast<float>(o.edgeTolerance);
    m->settings.jitter = o.jitter;
    m->settings.integrator = mIntegrator;
    // Either weight given: both as the options say (the other at its direct-light default).
    if (o.rangeSigma || o.shepardPower) {
        const passes::InterpolateSettings defaults;
        m->settings.noisySampleWeights = false;
        m->settings.interpolation.rangeSigma =
            static_cast<float>(o.rangeSigma.value_or(defaults.rangeSigma));
        m->settings.interpolation.shepardPower =
            static_cast<float>(o.shepardPower.value_or(defaults.shepardPower));
    }
    m->settings.foveaRaysPerPoint = o.integrator.foveaRays;
    if (mThesis) {
        passes::TaaSettings unused;
        render::useThesisReconstruction(m->settings, unused);
    }
    return m;
}

// Guenter et al. 2012's eccentricity layers on the eval display (its bands' geometry), at
// slope A with three layers, --rays-per-point rays per layer pixel, their own per-layer history
// with --taa, and the outer layers at half rate (section 4.3).
std::unique_ptr<render::EccentricityLayers> EvalRun::makeLayers() {
    render::EccentricityLayerSettings s = layerSettings("A", 3, mOptions.raysPerPoint);
    s.jitter = mOptions.jitter;
    s.temporal = mOptions.taa;
    s.lod = mOptions.lod;
    s.display = mGeometry.display;
    return std::make_unique<render::EccentricityLayers>(mRenderer->methodContext(), s);
}

// The foveated frame after `frames` frames of the same view (TAA settled). Layers trace their
// outer layers every other frame: their rays are the mean of the last two frames.
RgbaImage EvalRun::foveatedFrame(render::FoveationMethod& m, const std::string& name,
                                 uint64_t& rays) {
    render::View v = mBase;
    v.name = name;
    v.post.taa = mOptions.taa;
    RgbaImage img;
    uint64_t previous = 0;
    const uint32_t frames = std::max(1u, mOptions.frames);
    mShooter->sequence(
        frames, [&](const FrameTick&) { return v; }, m,
        [&](const FrameTick&, RgbaImage shot, uint64_t r) {
            img = std::move(shot);
            previous = std::exchange(rays, r);
        });
    if (mOptions.method == "layers" && frames > 1) {
        rays = (rays + previous) / 2;
    }
    return img;
}

Baselines EvalRun::baselines(uint64_t rays) {
    const Geometry& g = mGeometry;
    Baselines b;
    std::tie(b.uw, b.uh) = uniformSize(rays, mOptions.raysPerPoint, g.width, g.height);
    render::FullResolution uniform(mRenderer->methodContext(),
                                   {mOptions.raysPerPoint, kSeed, mIntegrator});
    render::View v = viewAt(b.uw, b.uh);
    v.name = "uniform";
    const RgbaImage low = mShooter->shot(v, uniform);
    b.bilinear = quality::upscale(low, g.width, g.height, quality::Upscale::Bilinear);
    b.bicubic = quality::upscale(low, g.width, g.height, quality::Upscale::CatmullRom);
    b.fullSpp = std::max<uint32_t>(
        1, static_cast<uint32_t>(std::lround(static_cast<double>(rays) / (g.width * g.height))));
    render::FullResolution full(mRenderer->methodContext(), {b.fullSpp, kSeed, mIntegrator});
    v = mBase;
    v.name = "full";
    b.fullRes = mShooter->shot(v, full);
    return b;
}

nlohmann::json EvalRun::summaryHead() {
    const Geometry& g = mGeometry;
    nlohmann::json summary;
    summary["device"] = mRenderer->context().deviceName();
    summary["scene"] = mOptions.scene;
    if (mOptions.hmd.empty()) {
        summary["profile"] = mOptions.profile;
    } else {
        summary["hmd"] = mOptions.hmd;
        summary["frustum_tangents"] = {{"left", mGeometry.frustum->left},
                                       {"right", mGeometry.frustum->right},
                                       {"up", mGeometry.frustum->up},
                                       {"down", mGeometry.frustum->down}};
        summary["viewing_distance"] = mGeometry.display.viewingDistance;
    }
    summary["width"] = g.width;
    summary["height"] = g.height;
    summary["gaze"] = {g.gaze.x, g.gaze.y};
    summary["pixels_per_degree"] = g.ppd;
    summary["reference_spp"] = !mOptions.reference.empty() ? nlohmann::json(mOptions.reference)
                                                           : nlohmann::json(mOptions.referenceSpp);
    if (mIntegrator.integrator != render::Integrator::Direct) {
        summary["integrator"] = integratorJson(mOptions.integrator);
    }
    summary["bands_deg"] = {"0-5", "5-10", "10-20", "20+"};
    summary["flip_ecc_ppd"] = nlohmann::json::array();
    for (std::size_t b = 0; b < kBands; ++b) {
        summary["flip_ecc_ppd"].push_back(g.ppd /
                                          quality::acuityFalloff(quality::kBandStartDeg[b]));
    }
    return summary;
}

// The still frame: foveated and the baselines, scored, with their error maps and the bars.
void EvalRun::stillFrame(nlohmann::json& summary) {
    const EvalOptions& o = mOptions;
    const Geometry& g = mGeometry;
    const bool layers = o.method == "layers";
    if (layers) {
        mFoveated = makeLayers();
    } else {
        mFoveated = makeFoveated(o.scale);
    }
    uint64_t rays = 0;
    const RgbaImage fov = foveatedFrame(*mFoveated, "foveated", rays);
    mTarget = {g.width, g.height, o.raysPerPoint, rays, settledGpuMs(mShooter->gpuMs(), layers)};
    writePng(mOut / "foveated.png", fov);
    nlohmann::json methods = nlohmann::json::object();
    std::vector<std::array<double, kBands>> bars;
    nlohmann::json plotSeries = nlohmann::json::array();
    {
        mProgress->step("scoring foveated (FLIP, PSNR, SSIM per band)");
        Scores s = scored(fov);
        s.json["rays"] = rays;
        mTarget.flipEcc = s.flipEcc;
        const auto* points = dynamic_cast<const render::PointSetMethod*>(mFoveated.get());
        const passes::InterpolateSettings weights =
            points ? points->interpolation() : passes::InterpolateSettings{};
        s.json["settings"] = {{"reconstruction", o.reconstruction},
                              {"interp", o.interp},
                              {"k", o.k},
                              {"rays_per_point", o.raysPerPoint},
                              {"scale", o.scale},
                              {"taa", o.taa},
                              {"frames", o.frames},
                              {"blend", o.blend},
                              {"edge_tolerance", o.edgeTolerance},
                              {"range_sigma", weights.rangeSigma},
                              {"shepard_power", weights.shepardPower},
                              {"still_clip", o.stillClipGamma},
                              {"eccentric_radius", o.eccentricRadius},
                              {"jitter", o.jitter}};
        if (layers) {
            const auto& ls = dynamic_cast<render::EccentricityLayers&>(*mFoveated).settings();
            s.json["settings"] = {{"method", "layers"},       {"slope", ls.slope},
                                  {"layers", ls.layers},      {"rays_per_pixel", ls.raysPerPixel},
                                  {"half_rate", ls.halfRate}, {"taa", o.taa},
                                  {"frames", o.frames},       {"jitter", o.jitter}};
        }
        methods["foveated"] = s.json;
        writePng(mOut / "flip_foveated.png", errorMapImage(s.flip, g.width, g.height));
        bars.push_back(s.flipBands);
        plotSeries.push_back({{"name", "foveated"}, {"colour", seriesColourHex(0)}});
    }
    if (o.baseline == "uniform") {
        const Baselines b = baselines(rays);
        const std::array<std::pair<const char*, const RgbaImage*>, 3> rows{
            {{"uniform_bilinear", &b.bilinear},
             {"uniform_catmull_rom", &b.bicubic},
             {"full_resolution", &b.fullRes}}};
        for (const auto& [name, img] : rows) {
            mProgress->step(std::string("scoring ") + name);
            Scores s = scored(*img);
            const bool full = std::string(name) == "full_resolution";
            s.json["rays"] = full ? static_cast<uint64_t>(b.fullSpp) * g.width * g.height
                                  : static_cast<uint64_t>(b.uw) * b.uh * o.raysPerPoint;
            s.json["size"] = full ? nlohmann::json{g.width, g.height} : nlohmann::json{b.uw, b.uh};
            s.json["rays_per_pixel"] = full ? b.fullSpp : o.raysPerPoint;
            methods[name] = s.json;
            writePng(mOut / ("flip_" + std::string(name) + ".png"),
                     errorMapImage(s.flip, g.width, g.height));
            writePng(mOut / (std::string(name) + ".png"), *img);
            plotSeries.push_back({{"name", name}, {"colour", seriesColourHex(bars.size())}});
            bars.push_back(s.flipBands);
        }
    }
    summary["methods"] = methods;
    double maxBar = 0.0;
    for (const auto& b : bars) {
        maxBar = std::max(maxBar, *std::max_element(b.begin(), b.end()));
    }
    writePng(mOut / "bands.png", bandBars(bars, maxBar * 1.1, seriesNames(plotSeries)));
    summary["plots"] = {
        {"bands.png", "FLIP per band (0-5, 5-10, 10-20, 20+ deg), one bar per method"},
        {"series", plotSeries}};
}

// A still view: whatever changes from frame to frame is the method's own flicker, measured
// after the `frames` the still frame settles for.
nlohmann::json EvalRun::stillSequence() {
    const uint32_t seqFrames = std::max(2u, mOptions.sequenceFrames);
    std::vector<Change> steps;
    RgbaImage last;
    render::View v = mBase;
    v.name = "still";
    v.post.taa = mOptions.taa;
    const uint32_t settle = std::max(1u, mOptions.frames) - 1;
    mShooter->sequence(
        settle + seqFrames, [&](const FrameTick&) { return v; }, *mFoveated,
        [&](const FrameTick& t, RgbaImage img, uint64_t) {
            if (t.index > settle) {
                steps.push_back(stillChange(last, img, mGeometry.bands));
            }
            last = std::move(img);
        });
    return changeJson(steps);
}

// A moving camera: each frame against the previous one reprojected through the geometry; the
// reference at one ray per pixel with the same seed every frame. A path-traced reference's
// samples change from frame to frame, so it runs the foveated frame's post chain (denoiser and
// TAA) to flicker no more than such a renderer would; a direct one needs no history.
nlohmann::json EvalRun::movingSequence() {
    const Geometry& g = mGeometry;
    const scene::CameraPath& path = *mInputs.path;
    const uint32_t seqFrames = std::max(2u, mOptions.sequenceFrames);
    render::FullResolution oneRay(mRenderer->methodContext(), {1, kSeed, mIntegrator});
    nlohmann::json moving = nlohmann::json::object();
    std::vector<scene::Camera> cams;
    std::vector<std::vector<float>> depths;
    for (uint32_t i = 0; i < seqFrames; ++i) {
        const double t = path.startMs() + (path.endMs() - path.startMs()) * i / (seqFrames - 1);
        cams.push_back(path.at(t, mCamera.yfov));
        mProgress->step("depth map " + std::to_string(i + 1) + "/" + std::to_string(seqFrames));
        depths.push_back(depthMap(*mRenderer, cams.back(), g.width, g.height));
    }
    for (const bool isRef : {false, true}) {
        std::vector<Change> steps;
        RgbaImage last;
        const auto view = [&](const FrameTick& t) {
            render::View v = mBase;
            v.camera = cams[t.index];
            v.name = isRef ? "moving_reference" : "moving_foveated";
            v.post.taa = (!isRef || pathTraced()) && mOptions.taa;
            return v;
        };
        render::FoveationMethod& method =
            isRef ? static_cast<render::FoveationMethod&>(oneRay) : *mFoveated;
        mShooter->sequence(
            seqFrames, view, method, [&](const FrameTick& t, RgbaImage img, uint64_t) {
                const uint32_t i = t.index;
                if (i > 0) {
                    steps.push_back(reprojectedChange(last, img, cams[i - 1], cams[i],
                                                      depths[i - 1], depths[i], g.bands));
                }
                last = std::move(img);
            });
        moving[isRef ? "reference" : "foveated"] = changeJson(steps);
    }
    moving["reference_taa"] = pathTraced() && mOptions.taa;
    moving["camera_path"] = mOptions.cameraPath;
    moving["frames"] = seqFrames;
    return moving;
}

// An animated scene playing at 90 Hz from --time: each foveated frame (its TAA history carried
// along the motion) against a reference rendered at the same instant, once the history has seen
// 8 frames of motion; and the same count of frames with the scene held at --time. Moving content
// that ghosts or smears shows as moving error above the still error.
nlohmann::json EvalRun::animatedSequence() {
    constexpr double kStepS = 1.0 / 90.0;
    constexpr uint32_t kMotionFrames = 8;
    const uint32_t n = std::max(kMotionFrames + 1, mOptions.sequenceFrames);
    const double t0 = mOptions.time;
    render::FullResolution reference(mRenderer->methodContext(),
                                     {mOptions.referenceSpp, kSeed, mIntegrator});
    std::vector<RgbaImage> refs;
    const auto at = [&](const FrameTick& t) { return t0 + kStepS * t.index; };
    const auto viewNamed = [&](const char* name, bool taa) {
        return [this, name, taa](const FrameTick&) {
            render::View v = mBase;
            v.name = name;
            v.post.taa = taa;
            return v;
        };
    };
    const auto groundTruth = [&](const FrameTick& t) {
        render::View v = viewNamed("animated_reference", false)(t);
        v.post.denoise.reset();
        return v;
    };
    mShooter->sequence(
        n, groundTruth, reference,
        [&](const FrameTick&, RgbaImage img, uint64_t) { refs.push_back(std::move(img)); }, at);
    std::array<double, kBands> moving{}, still{};
    const auto meanInto = [&](std::array<double, kBands>& sum, const RgbaImage& img,
                              const RgbaImage& ref) {
        const Scores s = score(img, ref, mGeometry, mBleedMask);
        for (std::size_t b = 0; b < kBands; ++b)
            sum[b] += s.flipEcc[b] / static_cast<double>(n - kMotionFrames);
    };
    mShooter->sequence(
        n, viewNamed("animated_foveated", mOptions.taa), *mFoveated,
        [&](const FrameTick& t, RgbaImage img, uint64_t) {
            if (t.index >= kMotionFrames) meanInto(moving, img, refs[t.index]);
        },
        at);
    mShooter->sequence(n, viewNamed("animated_still", mOptions.taa), *mFoveated,
                       [&](const FrameTick& t, RgbaImage img, uint64_t) {
                           if (t.index >= kMotionFrames) meanInto(still, img, refs.front());
                       });
    mRenderer->setSceneTime(t0);
    std::array<double, kBands> ratio{};
    for (std::size_t b = 0; b < kBands; ++b)
        ratio[b] = moving[b] / std::max(still[b], 1e-12);
    return {{"frames", n},
            {"step_ms", kStepS * 1e3},
            {"time_s", t0},
            {"flip_ecc_moving", bandsJson(moving)},
            {"flip_ecc_still", bandsJson(still)},
            {"moving_over_still", bandsJson(ratio)}};
}

// Smooth pursuit over a still scene: the point set follows the gaze, the scene stays. With the
// path integrator, also the uniform path tracer (one path per pixel, the same denoiser and TAA)
// under the same gaze: its samples and its denoiser's fovea move too.
nlohmann::json EvalRun::pursuitSequence() {
    nlohmann::json pj = pursuitOf(*mFoveated, "pursuit");
    if (pathTraced()) {
        render::FullResolution uniform(mRenderer->methodContext(), {1, kSeed, mIntegrator});
        pj["uniform"] = pursuitOf(uniform, "pursuit_uniform");
    }
    pj["trace"] = mOptions.pursuit;
    return pj;
}

// Frame-to-frame change of `method` following the pursuit trace (see pursuitSequence).
nlohmann::json EvalRun::pursuitOf(render::FoveationMethod& method, const char* name) {
    const Geometry& g = mGeometry;
    std::vector<Change> steps;
    RgbaImage last;
    const auto& samples = mInputs.pursuit->samples();
    const std::size_t n =
        std::min<std::size_t>(samples.size(), std::max(2u, mOptions.sequenceFrames));
    const uint32_t settle = std::max(1u, mOptions.frames) - 1; // at the first gaze, as a still view
    double overall = 0.0;
    const auto view = [&](const FrameTick& t) {
        const std::size_t i = t.index < settle ? 0 : t.index - settle;
        render::View v = mBase;
        v.name = name;
        v.post.taa = mOptions.taa;
        v.gaze = clampToImage(samples[i].position, g.width, g.height);
        return v;
    };
    mShooter->sequence(
        settle + static_cast<uint32_t>(n), view, method,
        [&](const FrameTick& t, RgbaImage img, uint64_t) {
            if (t.index > settle) {
                const std::vector<uint8_t> one(img.count(), 0);
                const Change all = stillChange(last, img, one);
                overall += all.share[0] / static_cast<double>(n - 1);
                steps.push_back(stillChange(
                    last, img, quality::bandMap(g.display, g.width, g.height, view(t).gaze)));
            }
            last = std::move(img);
        });
    nlohmann::json pj = changeJson(steps);
    pj["changed_percent_all"] = overall;
    pj["frames"] = n;
    // What the pursuit leaves on screen: the last frame against the reference (the camera
    // stayed), in bands around the gaze it was rendered for. A history that holds on to what
    // the periphery's sparse samples showed changes little from frame to frame but keeps the
    // new fovea blurred; this says which.
    Geometry at = g;
    at.gaze = view(FrameTick{.index = settle + static_cast<uint32_t>(n) - 1}).gaze;
    at.bands = quality::bandMap(g.display, g.width, g.height, at.gaze);
    pj["flip_ecc_last"] = bandsJson(score(last, mRef, at, {}).flipEcc);
    writePng(mOut / (std::string(name) + "_last.png"), last);
    return pj;
}

// Quality against rays: the foveated method at sparser scales and the uniform baseline at the
// same rays, mean FLIP over the two foveal bands and over the image.
void EvalRun::sweep(nlohmann::json& summary) {
    nlohmann::json sweep = nlohmann::json::array();
    std::vector<std::vector<std::pair<double, double>>> curves(2);
    for (const double scale : {1.0, 1.5, 2.0, 3.0}) {
        auto m = scale == mOptions.scale ? std::move(mFoveated) : makeFoveated(scale);
        uint64_t r = 0;
        const RgbaImage img = foveatedFrame(*m, "sweep_foveated", r);
        mProgress->step("scoring the sweep at scale " + std::to_string(scale).substr(0, 3));
        const Scores fs = scored(img);
        const Baselines b = baselines(r);
        Scores us = scored(b.bilinear);
        us.json["rays"] = static_cast<uint64_t>(b.uw) * b.uh * mOptions.raysPerPoint;
        sweep.push_back({{"scale", scale},
                         {"rays", r},
                         {"foveated", fs.json},
                         {"uniform_bilinear", us.json},
                         {"uniform_size", {b.uw, b.uh}}});
        curves[0].emplace_back(static_cast<double>(r), fs.json["flip_mean"].get<double>());
        curves[1].emplace_back(static_cast<double>(r), us.json["flip_mean"].get<double>());
        mFoveated = std::move(m);
    }
    summary["sweep"] = sweep;
    writePng(mOut / "curves.png", curvesImage(curves, {"foveated", "uniform_bilinear"}));
    summary["plots"]["curves.png"] =
        "mean FLIP against rays (log): foveated (series 0) and uniform bilinear (series 1)";
}

// One --match candidate: the uniform render of width x height at `raysPerPixel`, settled with
// the foveated frame's TAA over as many frames (the ray seed changes every frame, as render's
// sequences do, so the history averages new rays), upscaled bilinearly as the uniform_bilinear
// baseline is, and scored against the reference. `picture` receives the upscaled frame.
MatchEntry EvalRun::matchCandidate(uint32_t width, uint32_t height, uint32_t raysPerPixel,
                                   RgbaImage& picture) {
    const Geometry& g = mGeometry;
    render::FullResolution uniform(mRenderer->methodContext(), {raysPerPixel, kSeed, mIntegrator});
    render::View v = viewAt(width, height);
    v.name = "match_" + std::to_string(width) + "x" + std::to_string(height) + "_" +
             std::to_string(raysPerPixel);
    v.post.taa = mOptions.taa;
    MatchEntry c{width, height, raysPerPixel};
    mShooter->sequence(
        std::max(1u, mOptions.frames),
        [&](const FrameTick& t) {
            uniform.settings.frameSeed = kSeed + t.index;
            return v;
        },
        uniform,
        [&](const FrameTick&, RgbaImage shot, uint64_t r) {
            picture = std::move(shot);
            c.rays = r;
        });
    c.gpuMs = settledGpuMs(mShooter->gpuMs(), false);
    if (width != g.width || height != g.height) {
        picture = quality::upscale(picture, g.width, g.height, quality::Upscale::Bilinear);
    }
    mProgress->step("scoring " + v.name);
    c.flipEcc = scored(picture).flipEcc;
    c.matches = noWorseInEveryBand(c.flipEcc, mTarget.flipEcc);
    return c;
}

// The foveated frame and its match timed in turns (kMatchTimingRounds rounds of a short still
// sequence each, the first frame, which resets TAA, left out; layers: a pair of frames, as their
// outer layers alternate). The search times its candidates minutes apart, over which the load
// of a shared machine drifts (a 1270-wide candidate once took 9.3 s, the 1280-wide one after it
// 15.4 s); in turns, each round's ratio compares frames timed under the same load, and the time
// ratio is their median.
constexpr uint32_t kMatchTimingRounds = 3;

nlohmann::json EvalRun::timedInTurns(const MatchEntry& match) {
    const bool pairs = mOptions.method == "layers";
    const uint32_t frames = pairs ? 3u : 2u;
    render::View fov = mBase;
    fov.name = "foveated_timed";
    fov.post.taa = mOptions.taa;
    render::FullResolution uniform(mRenderer->methodContext(),
                                   {match.raysPerPixel, kSeed, mIntegrator});
    render::View v = viewAt(match.width, match.height);
    v.name = "match_timed";
    v.post.taa = mOptions.taa;
    const auto ignore = [](const FrameTick&, RgbaImage, uint64_t) {};
    nlohmann::json t = {{"rounds", kMatchTimingRounds},
                        {"foveated_gpu_ms", nlohmann::json::array()},
                        {"match_gpu_ms", nlohmann::json::array()},
                        {"round_ratios", nlohmann::json::array()}};
    std::vector<double> ratios;
    for (uint32_t round = 0; round < kMatchTimingRounds; ++round) {
        mShooter->sequence(
            frames, [&](const FrameTick&) { return fov; }, *mFoveated, ignore);
        const double fovMs = settledGpuMs(mShooter->gpuMs(), pairs);
        mShooter->sequence(
            frames,
            [&](const FrameTick& tick) {
                uniform.settings.frameSeed = kSeed + tick.index;
                return v;
            },
            uniform, ignore);
        const double matchMs = settledGpuMs(mShooter->gpuMs(), false);
        t["foveated_gpu_ms"].push_back(fovMs);
        t["match_gpu_ms"].push_back(matchMs);
        ratios.push_back(fovMs > 0.0 ? matchMs / fovMs : 0.0);
        t["round_ratios"].push_back(ratios.back());
    }
    std::sort(ratios.begin(), ratios.end());
    t["time_ratio"] = ratios[ratios.size() / 2];
    return t;
}

// Where --match-doublings is unset: up to 8x the foveated rays per point.
constexpr uint32_t kMatchDoublings = 3;

// The speed-up at equal picture quality: the cheapest uniform render whose flip_ecc is no higher
// than the foveated frame's in every band, found by findLowestMatch over its width (uniform: at
// the foveated rays per point, from the size that spends the foveated rays up to full size, to
// 2 % in pixels) or its rays per pixel at full size (full: exact), at most 8 candidates. Where
// even full size does not match, `uniform` doubles its rays per pixel (up to --match-doublings
// times) and searches the width again from full size: a foveated frame that spends more paths
// in its fovea (--fovea-rays) is matched only by a uniform tracer with more paths per pixel.
void EvalRun::match(nlohmann::json& summary) {
    const EvalOptions& o = mOptions;
    const Geometry& g = mGeometry;
    const bool full = o.match == "full";
    const uint32_t doublings = full ? 0 : o.matchDoublings.value_or(kMatchDoublings);
    MatchSearchLimits limits{.maxTries = 8};
    if (full) {
        const double equal =
            static_cast<double>(mTarget.rays) / (static_cast<double>(g.width) * g.height);
        limits.highest = o.raysPerPoint;
        limits.start =
            std::clamp<uint32_t>(static_cast<uint32_t>(std::lround(equal)), 1, o.raysPerPoint);
        limits.tolerance = 0.0;
    } else {
        limits.highest = g.width;
        limits.start =
            std::min(g.width, uniformSize(mTarget.rays, o.raysPerPoint, g.width, g.height).first);
        limits.tolerance = std::sqrt(1.02) - 1.0; // 2 % in pixels
    }
    std::vector<MatchEntry> tried;
    RgbaImage picture, matched;
    const RaysMatchResult found = findLowestMatchDoublingRays(
        limits, o.raysPerPoint, doublings, [&](uint32_t n, uint32_t rpp) {
            const uint32_t h = std::max<uint32_t>(
                1, static_cast<uint32_t>(std::lround(static_cast<double>(n) * g.height / g.width)));
            tried.push_back(full ? matchCandidate(g.width, g.height, n, picture)
                                 : matchCandidate(n, h, rpp, picture));
            if (tried.back().matches) {
                matched = std::move(picture); // the search's last match is its answer
            }
            return tried.back().matches;
        });
    const MatchSearchResult& r = found.search;
    const uint32_t rpp = found.raysPerPixel;
    nlohmann::json m = {{"against", o.match},
                        {"criterion", "flip_ecc no higher in every band"},
                        {"upscale", full ? "none" : "bilinear"},
                        {"doublings", doublings},
                        {"foveated",
                         {{"method", o.method},
                          {"rays", mTarget.rays},
                          {"gpu_ms_median", mTarget.gpuMs},
                          {"flip_ecc", bandsJson(mTarget.flipEcc)}}},
                        {"tried", nlohmann::json::array()},
                        {"converged", r.converged},
                        {"match", nullptr},
                        {"below", nullptr},
                        {"ray_ratio", nullptr},
                        {"time_ratio", nullptr}};
    const auto entryOf = [&](uint32_t n) { // in the last search (rays per pixel `rpp`)
        return *std::find_if(tried.rbegin(), tried.rend(), [&](const MatchEntry& e) {
            return full ? e.raysPerPixel == n : e.width == n && e.raysPerPixel == rpp;
        });
    };
    for (const MatchEntry& e : tried) {
        m["tried"].push_back(matchEntryJson(e));
    }
    if (r.below != 0) {
        m["below"] = matchEntryJson(entryOf(r.below));
    }
    if (r.match) {
        const MatchEntry e = entryOf(*r.match);
        m["match"] = matchEntryJson(e);
        m["ray_ratio"] = static_cast<double>(e.rays) / static_cast<double>(mTarget.rays);
        mProgress->step("timing the foveated frame and its match in turns");
        m["timed_in_turns"] = timedInTurns(e);
        m["time_ratio"] = m["timed_in_turns"]["time_ratio"];
        writePng(mOut / ("match_" + o.match + ".png"), matched);
    } else {
        // No match: the candidate that came closest, by its worst band.
        m["best"] = matchEntryJson(*std::min_element(
            tried.begin(), tried.end(), [&](const MatchEntry& a, const MatchEntry& b) {
                return worstBandRatio(a, mTarget) < worstBandRatio(b, mTarget);
            }));
    }
    summary["match"] = m;
}

// The fovea as the path tracer leaves it (issue 49's fovea target): within 5 degrees, the
// foveated frame's FLIP against a full-resolution frame that traces as many paths per display
// pixel as the foveated frame's points there do (the points within 5 degrees times their
// paths, over the disc's pixels on screen), with the same denoiser and TAA. In 0-5 degrees
// flip_ecc is FLIP (the acuity ratio there is 1).
void EvalRun::foveaCheck(nlohmann::json& summary) {
    const auto* points = dynamic_cast<const render::PointSetMethod*>(mFoveated.get());
    if (points == nullptr || !pathTraced()) {
        return;
    }
    const Geometry& g = mGeometry;
    const auto& d = points->pointSet().params().display;
    const double radius = d.viewingDistance * d.width * std::tan(5.0 * std::numbers::pi / 180.0);
    std::size_t pixels = 0;
    for (uint32_t y = 0; y < g.height; ++y) {
        for (uint32_t x = 0; x < g.width; ++x) {
            const glm::dvec2 p = glm::dvec2(x, y) - glm::dvec2(mBase.gaze);
            pixels += glm::dot(p, p) <= radius * radius ? 1 : 0;
        }
    }
    const uint32_t paths = points->settings.foveaRaysPerPoint > 0
                               ? points->settings.foveaRaysPerPoint
                               : points->settings.raysPerPoint;
    const double perPixel = static_cast<double>(points->pointsWithin(mBase, radius) * paths) /
                            static_cast<double>(std::max<std::size_t>(pixels, 1));
    const auto spp = std::max<uint32_t>(1, static_cast<uint32_t>(std::lround(perPixel)));
    mProgress->step("the fovea against full resolution at " + std::to_string(spp) + " paths");
    RgbaImage picture;
    const MatchEntry full = matchCandidate(g.width, g.height, spp, picture);
    summary["fovea_check"] = {{"radius_px", radius},
                              {"paths_per_pixel_foveated", perPixel},
                              {"full_resolution_rays_per_pixel", spp},
                              {"flip_0_5_foveated", mTarget.flipEcc[0]},
                              {"flip_0_5_full_resolution", full.flipEcc[0]},
                              {"no_worse", mTarget.flipEcc[0] <= full.flipEcc[0]}};
}

nlohmann::json EvalRun::run() {
    nlohmann::json summary = summaryHead();
    stillFrame(summary);
    // Temporal stability.
    nlohmann::json temporal = nlohmann::json::object();
    if (mOptions.temporal) temporal["still"] = stillSequence();
    if (mInputs.path) temporal["moving"] = movingSequence();
    if (mInputs.pursuit) temporal["pursuit"] = pursuitSequence();
    if (mOptions.temporal && mRenderer->animated()) temporal["animated"] = animatedSequence();
    if (!temporal.empty()) {
        summary["temporal"] = temporal;
    }
    if (mOptions.sweep) sweep(summary);
    if (!mOptions.match.empty()) {
        foveaCheck(summary);
        match(summary);
    }
    io::writeFileAtomic(mOut / "eval.json", summary.dump(2) + "\n");
    mFolder.commit();
    return summary;
}

// A --match entry as "W x H at R rays/px: N M rays, T ms GPU".
std::string matchEntryText(const nlohmann::json& e) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%ux%u at %u rays/px: %.3f M rays, %.3f ms GPU",
                  e["size"][0].get<uint32_t>(), e["size"][1].get<uint32_t>(),
                  e["rays_per_pixel"].get<uint32_t>(),
                  static_cast<double>(e["rays"].get<uint64_t>()) * 1e-6,
                  e["gpu_ms_median"].get<double>());
    return buf;
}

// --match for people: the sizes tried, both frames, and the ratios, or that none matched.
std::string matchText(const nlohmann::json& m) {
    std::ostringstream t;
    const bool full = m["against"] == "full";
    t << "match " << m["against"].get<std::string>() << " (" << m["criterion"].get<std::string>()
      << (full ? ", full size" : ", upscaled bilinearly") << "), tried:";
    for (const auto& e : m["tried"]) {
        t << " " << e["size"][0].get<uint32_t>() << "x" << e["size"][1].get<uint32_t>() << "@"
          << e["rays_per_pixel"].get<uint32_t>() << (e["matches"].get<bool>() ? " yes," : " no,");
    }
    t << (m["converged"].get<bool>() ? " converged" : " not converged (8 candidates)") << "\n";
    const auto& f = m["foveated"];
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3f M rays, %.3f ms GPU",
                  static_cast<double>(f["rays"].get<uint64_t>()) * 1e-6,
                  f["gpu_ms_median"].get<double>());
    t << "  foveated: " << buf << "\n";
    if (m["match"].is_null()) {
        t << "  no match: even full resolution at the foveated rays per point has a higher "
             "flip_ecc in some band; the closest: "
          << matchEntryText(m["best"]) << "\n";
        return t.str();
    }
    t << "  uniform:  " << matchEntryText(m["match"]) << "\n";
    if (!m["below"].is_null()) {
        t << "  (not matching just below: " << matchEntryText(m["below"]) << ")\n";
    }
    if (m.contains("timed_in_turns")) {
        const auto& turns = m["timed_in_turns"];
        t << "  timed in turns (GPU ms, foveated / uniform):";
        for (std::size_t i = 0; i < turns["round_ratios"].size(); ++i) {
            std::snprintf(buf, sizeof buf, " %.1f / %.1f,",
                          turns["foveated_gpu_ms"][i].get<double>(),
                          turns["match_gpu_ms"][i].get<double>());
            t << buf;
        }
        t << " median ratio\n";
    }
    const double rays = m["ray_ratio"].get<double>();
    const double time = m["time_ratio"].is_null() ? 0.0 : m["time_ratio"].get<double>();
    std::snprintf(buf, sizeof buf, "%.2f", rays);
    t << "the foveated frame needs " << buf << " x fewer rays and ";
    std::snprintf(buf, sizeof buf, "%.2f", time);
    t << buf << " x less time for the same picture"
      << (rays < 1.0 || time < 1.0 ? " (below 1: the uniform frame is the cheaper)" : "") << "\n";
    return t.str();
}

} // namespace

nlohmann::json runEval(const EvalOptions& o) {
    EvalRun run(o);
    return run.run();
}

std::string evalText(const nlohmann::json& s) {
    std::ostringstream t;
    char buf[256];
    std::snprintf(buf, sizeof buf, "%s, %s %ux%u, gaze (%.0f, %.0f), %.1f px/deg, reference %s\n",
                  s["scene"].get<std::string>().c_str(),
                  (s.contains("hmd") ? s["hmd"] : s["profile"]).get<std::string>().c_str(),
                  s["width"].get<uint32_t>(), s["height"].get<uint32_t>(),
                  s["gaze"][0].get<double>(), s["gaze"][1].get<double>(),
                  s["pixels_per_degree"].get<double>(), s["reference_spp"].dump().c_str());
    t << buf;
    t << "method                  rays      FLIP 0-5   5-10  10-20    20+ | flip_ecc 5-10 10-20  "
         "20+ | PSNR 0-5  SSIM 0-5 | bleed | FLIP all\n";
    for (const auto& [name, m] : s["methods"].items()) {
        const auto& b = m["bands"];
        std::snprintf(buf, sizeof buf,
                      "%-20s %9llu   %6.4f %6.4f %6.4f %6.4f |        %6.4f %6.4f %6.4f | %7.2f  "
                      "%7.4f | %5.2f |   %6.4f\n",
                      name.c_str(), static_cast<unsigned long long>(m["rays"].get<uint64_t>()),
                      b["0-5"]["flip"].get<double>(), b["5-10"]["flip"].get<double>(),
                      b["10-20"]["flip"].get<double>(), b["20+"]["flip"].get<double>(),
                      b["5-10"]["flip_ecc"].get<double>(), b["10-20"]["flip_ecc"].get<double>(),
                      b["20+"]["flip_ecc"].get<double>(), b["0-5"]["psnr_db"].get<double>(),
                      b["0-5"]["ssim"].get<double>(), m["bleed_mad"].get<double>(),
                      m["flip_mean"].get<double>());
        t << buf;
    }
    if (s.contains("temporal")) {
        for (const auto& [name, v] : s["temporal"].items()) {
            t << "temporal " << name << ": " << v.dump() << "\n";
        }
    }
    if (s.contains("fovea_check")) {
        const auto& f = s["fovea_check"];
        char line[200];
        std::snprintf(line, sizeof line,
                      "fovea (0-5 deg): FLIP %.4f at %.1f paths per pixel; full resolution at %u: "
                      "%.4f\n",
                      f["flip_0_5_foveated"].get<double>(),
                      f["paths_per_pixel_foveated"].get<double>(),
                      f["full_resolution_rays_per_pixel"].get<uint32_t>(),
                      f["flip_0_5_full_resolution"].get<double>());
        t << line;
    }
    if (s.contains("match")) {
        t << matchText(s["match"]);
    }
    return t.str();
}

} // namespace gt::app
