// `gazetrace bench --suite scale` (scale_bench.hpp). Per profile one renderer, so what a
// profile allocated is gone before the next; the profiles run from the fewest pixels per eye to
// the most, so the process's peak RSS read after each one is mostly that profile's own.
//
// Timing follows `bench`: frames waited for one at a time, results left on the GPU, unmeasured
// frames first until half a second has passed (at least one), then the methods alternated frame
// by frame with the reference at the same rays, so drift of a shared machine hits all alike;
// ratios are medians of each round's reference over its method. The layers update their middle
// and outer layers at half rate (Guenter et al. 2012, section 4.3): each of their samples is the
// mean of two consecutive frames.
#include "scale_bench.hpp"
#include "bench_timing.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <new>

#include <sys/resource.h>
#include <unistd.h>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "display/hmd_profile.hpp"
#include "eccentricity_layers.hpp"
#include "eval_plots.hpp"
#include "foveation/point_set_cache.hpp"
#include "frame_loop.hpp"
#include "full_resolution.hpp"
#include "option_parsing.hpp"
#include "output_target.hpp"
#include "point_set_method.hpp"
#include "renderer.hpp"
#include "scene/image_io.hpp"
#include "stereo_rig.hpp"
#include "vk/context.hpp"

namespace gt::app {

namespace {

using Clock = std::chrono::steady_clock;

constexpr std::array<uint32_t, 2> kRays{1, 8};
constexpr uint32_t kShepardK = 10;

double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

// The process's peak resident set so far (getrusage: kilobytes on Linux).
double peakRssMb() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<double>(u.ru_maxrss) * 1024.0 / 1e6;
}

// Memory figures are counted in bytes, so that a difference of equal sums is exactly zero.
int64_t gpuUsedBytes(vk::Context& ctx) {
    return static_cast<int64_t>(ctx.allocator().stats().usedBytes);
}

double mb(int64_t bytes) {
    return static_cast<double>(bytes) / 1e6;
}

// The headsets to measure, fewest pixels per eye first.
std::vector<display::HmdProfile> profilesOf(const ScaleBenchOptions& o) {
    std::vector<display::HmdProfile> out;
    if (o.profiles.empty()) {
        for (const display::HmdModel m : display::kHmdModels) {
            out.push_back(display::hmdProfile(m));
        }
    } else {
        for (const std::string& name : o.profiles) {
            out.push_back(hmdProfile(name));
        }
    }
    for (display::HmdProfile& p : out) {
        if (o.eyeSize) {
            // Same viewing distance in eye widths: the same headset with fewer pixels.
            p.pointSetProfile.width = o.eyeSize->first;
            p.pointSetProfile.height = o.eyeSize->second;
        }
        if (o.eyeDistance) {
            p.pointSetProfile.viewingDistance = *o.eyeDistance;
        }
        // The eye's image is its point set's display (a point set is built for one size).
        p.eyeWidth = p.pointSetProfile.width;
        p.eyeHeight = p.pointSetProfile.height;
    }
    std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
        return static_cast<uint64_t>(a.eyeWidth) * a.eyeHeight <
               static_cast<uint64_t>(b.eyeWidth) * b.eyeHeight;
    });
    return out;
}

// What a profile or method too large for the device or memory throws (a stop request is no
// gt::Error and ends the run).
bool outOfReach(const std::exception& e) {
    return dynamic_cast<const Error*>(&e) != nullptr ||
           dynamic_cast<const std::bad_alloc*>(&e) != nullptr;
}

struct Sample {
    double gpuMs = 0.0, wallMs = 0.0, rays = 0.0;
};

// One method as the suite runs it: its view's name, post chain and what it built.
struct Slot {
    std::string label; // reference, nn, msm, layers
    render::FoveationMethod* method = nullptr;
    bool taa = false;
    int framesPerSample = 1;
    int64_t gpuBytes = 0; // allocator growth from its construction through its warm-up frames
    // Of which its view's frame images at the eye's size (histories, radiance, output): every
    // method at that size holds such images. A method's coarser grids (layers) are its own.
    int64_t eyeImageBytes = 0;
    std::string error; // why it could not be set up; then it is not measured
};

// One row: a method at one ray count, its samples and the reference's of the same rounds.
struct Row {
    std::string label;
    uint32_t rays = 1;
    std::vector<Sample> samples;
    std::vector<double> timeRatio, wallRatio;
};

class ProfileRun {
public:
    ProfileRun(const ScaleBenchOptions& o, display::HmdProfile hmd,
               const std::filesystem::path& cache)
        : mOptions(o), mHmd(std::move(hmd)), mCache(cache),
          mRenderer({.scene = o.common.scene,
                     .deviceOverride = deviceRequest(),
                     .sceneLoad = gltfLoadOptions()}),
          mRig(mHmd, false), mIntegrator(parseIntegrator(o.common.integrator)) {}

    nlohmann::json run();
    [[nodiscard]] render::Renderer& renderer() noexcept { return mRenderer; }

private:
    [[nodiscard]] render::View view(const Slot& s) const;
    Sample frame(const Slot& s);
    Sample sample(const Slot& s);
    void warmUp(const Slot& s);
    void setUp(Slot& s, const std::function<void()>& construct,
               const std::function<void()>& release);
    void setUpAll(std::vector<Slot>& slots, const foveation::PointSetParams& params);
    void setRays(uint32_t rays, std::vector<Slot>& slots);
    std::vector<Row> measure(uint32_t rays, const std::vector<Slot>& slots);
    [[nodiscard]] nlohmann::json buildJson() const;
    [[nodiscard]] nlohmann::json rowJson(const Row& r, const Slot& s, const Row& reference) const;

    const ScaleBenchOptions& mOptions;
    display::HmdProfile mHmd;
    std::filesystem::path mCache;
    render::Renderer mRenderer;
    render::StereoRig mRig;
    render::DiscardTarget mDiscard;
    std::optional<render::FullResolution> mReference;
    std::optional<render::PointSetMethod> mNearest, mShepard;
    std::optional<render::EccentricityLayers> mLayers;
    render::EccentricityLayerSettings mLayerSettings;
    // The point set as loadOrGenerate gave it before the methods loaded it from the cache:
    // the time it took, and whether it came from the cache.
    double mSetMs = 0.0;
    bool mSetCached = false;
    render::IntegratorSettings mIntegrator; // the reference's and the point sets'
};

// The left eye, looking straight ahead (its optical axis), no lens: the lens pass costs every
// method the same.
render::View ProfileRun::view(const Slot& s) const {
    render::PostSettings post;
    post.taa = s.taa;
    if (!mLayers || s.method != &*mLayers) post.denoise = parseDenoise(mOptions.common.integrator);
    render::View v = mRig.views(mRenderer.scene().camera, render::StereoGaze{}, *s.method, post,
                                mRenderer.scene().exposure)[0];
    v.name = s.label; // its own history and transient resources
    return v;
}

Sample ProfileRun::frame(const Slot& s) {
    const render::FrameResult f = renderOneFrame(mRenderer, view(s), mDiscard);
    return {f.timings ? f.timings->gpuMs : 0.0, f.wallMs,
            f.views.empty() ? 0.0 : static_cast<double>(f.views.front().rays)};
}

Sample ProfileRun::sample(const Slot& s) {
    Sample sum;
    for (int i = 0; i < s.framesPerSample; ++i) {
        const Sample f = frame(s);
        sum.gpuMs += f.gpuMs / s.framesPerSample;
        sum.wallMs += f.wallMs / s.framesPerSample;
        sum.rays += f.rays / s.framesPerSample;
    }
    return sum;
}

void ProfileRun::warmUp(const Slot& s) {
    double ms = 0.0;
    do {
        ms += frame(s).wallMs;
    } while (ms < kWarmUpMs);
}

// Constructs a method and runs its warm-up frames (which build its tables), and records how much
// device memory that took: its buffers, tables and its view's frame resources.
void ProfileRun::setUp(Slot& s, const std::function<void()>& construct,
                       const std::function<void()>& release) {
    const VkExtent2D eye{mHmd.eyeWidth, mHmd.eyeHeight};
    const int64_t before = gpuUsedBytes(mRenderer.context());
    const auto imagesBefore = static_cast<int64_t>(mRenderer.frameImageBytes(eye));
    try {
        construct();
        warmUp(s);
    } catch (const std::exception& e) {
        // A method the device or memory cannot hold (a table past a texel-buffer limit) is
        // left out and said so; the others still run. Without the reference nothing can be.
        if (s.label == "reference" || !outOfReach(e)) {
            throw;
        }
        release();
        s.method = nullptr;
        s.error = e.what();
        std::fprintf(stderr, "gazetrace: %s, %s: %s\n", mHmd.name.c_str(), s.label.c_str(),
                     e.what());
        return;
    }
    s.gpuBytes = gpuUsedBytes(mRenderer.context()) - before;
    s.eyeImageBytes = static_cast<int64_t>(mRenderer.frameImageBytes(eye)) - imagesBefore;
}

// Rounds of one frame (or sample) per method, the reference first; a method left out at set-up
// has no samples.
std::vector<Row> ProfileRun::measure(uint32_t rays, const std::vector<Slot>& slots) {
    std::vector<Row> rows;
    rows.reserve(slots.size());
    for (const Slot& s : slots) {
        rows.push_back({s.label, rays, {}, {}, {}});
    }
    for (uint32_t i = 0; i < mOptions.frames; ++i) {
        for (std::size_t m = 0; m < slots.size(); ++m) {
            if (slots[m].method != nullptr) {
                rows[m].samples.push_back(sample(slots[m]));
            }
        }
        const Sample& ref = rows.front().samples.back();
        for (Row& r : rows) {
            if (r.samples.size() <= i) {
                continue;
            }
            const Sample& x = r.samples.back();
            r.timeRatio.push_back(x.gpuMs > 0.0 ? ref.gpuMs / x.gpuMs : 0.0);
            r.wallRatio.push_back(x.wallMs > 0.0 ? ref.wallMs / x.wallMs : 0.0);
        }
    }
    return rows;
}

nlohmann::json nullable(bool measured, double v) {
    return measured ? nlohmann::json(v) : nlohmann::json(nullptr);
}

nlohmann::json ProfileRun::rowJson(const Row& r, const Slot& s, const Row& reference) const {
    if (!s.error.empty()) {
        return {{"method", r.label}, {"rays_per_sample", r.rays}, {"error", s.error}};
    }
    std::vector<double> gpu, wall, rays;
    for (const Sample& x : r.samples) {
        gpu.push_back(x.gpuMs);
        wall.push_back(x.wallMs);
        rays.push_back(x.rays);
    }
    std::vector<double> refRays;
    for (const Sample& x : reference.samples) {
        refRays.push_back(x.rays);
    }
    const double raysMedian = median(rays);
    const double rayRatio = raysMedian > 0.0 ? median(refRays) / raysMedian : 0.0;
    const double timeRatio = median(r.timeRatio);
    const render::PointSetMethod* ps = r.label == "nn"    ? &*mNearest
                                       : r.label == "msm" ? &*mShepard
                                                          : nullptr;
    const bool table = r.label == "msm";
    const double setMb =
        ps ? static_cast<double>(ps->pointSet().points().size() * sizeof(foveation::Point)) / 1e6
           : 0.0;
    const double indexMb = ps ? ps->neighbourIndexMb() : 0.0;
    const double tableMb = table ? ps->knnTablePrepared().mb : 0.0;
    return {{"method", r.label},
            {"k", r.label == "msm" ? nlohmann::json(kShepardK) : nlohmann::json(nullptr)},
            {"rays_per_sample", r.rays},
            {"points", raysMedian / r.rays},
            {"rays", raysMedian},
            {"ray_ratio", rayRatio},
            {"gpu_ms", median(gpu)},
            {"wall_ms", median(wall)},
            {"time_ratio", timeRatio},
            {"wall_time_ratio", median(r.wallRatio)},
            {"efficiency", rayRatio > 0.0 ? timeRatio / rayRatio : 0.0},
            {"frames", r.samples.size()},
            {"frames_per_sample", s.framesPerSample},
            {"set_mb", nullable(ps, setMb)},
            {"neighbour_index_mb", nullable(ps, indexMb)},
            {"knn_table_mb", nullable(table, tableMb)},
            {"gpu_mb", mb(s.gpuBytes)},
            {"images_mb", mb(s.eyeImageBytes)},
            // Its GPU buffers and grids: what it allocated beyond its view's images.
            {"method_mb",
             setMb + indexMb + tableMb + mb(std::max<int64_t>(0, s.gpuBytes - s.eyeImageBytes))}};
}

// Each method built and warmed up in turn at the first ray count.
void ProfileRun::setUpAll(std::vector<Slot>& slots, const foveation::PointSetParams& params) {
    const render::MethodContext mc = mRenderer.methodContext();
    mLayerSettings.display = mHmd.pointSetProfile;
    mLayerSettings.raysPerPixel = kRays.front();
    setUp(
        slots[0],
        [&] {
            mReference.emplace(mc, passes::ReferenceSettings{kRays.front(), 0, mIntegrator});
            slots[0].method = &*mReference;
        },
        [&] { mReference.reset(); });
    setUp(
        slots[1],
        [&] {
            mNearest.emplace(mc, params, mCache);
            mNearest->settings.raysPerPoint = kRays.front();
            mNearest->settings.interpolation.method = passes::Interpolation::Nearest;
            mNearest->settings.integrator = mIntegrator;
            mNearest->settings.foveaRaysPerPoint = mOptions.common.integrator.foveaRays;
            slots[1].method = &*mNearest;
        },
        [&] { mNearest.reset(); });
    setUp(
        slots[2],
        [&] {
            mShepard.emplace(mc, params, mCache);
            mShepard->settings.raysPerPoint = kRays.front();
            mShepard->settings.interpolation.method = passes::Interpolation::Shepard;
            mShepard->settings.interpolation.k = kShepardK;
            mShepard->settings.integrator = mIntegrator;
            mShepard->settings.foveaRaysPerPoint = mOptions.common.integrator.foveaRays;
            slots[2].method = &*mShepard;
        },
        [&] { mShepard.reset(); });
    setUp(
        slots[3],
        [&] {
            mLayers.emplace(mc, mLayerSettings);
            slots[3].method = &*mLayers;
        },
        [&] { mLayers.reset(); });
}

// The methods at another ray count (the layers' is a setting of their construction), warmed up.
void ProfileRun::setRays(uint32_t rays, std::vector<Slot>& slots) {
    mReference->settings = {rays, 0, mIntegrator};
    for (std::optional<render::PointSetMethod>* m : {&mNearest, &mShepard}) {
        if (m->has_value()) {
            (*m)->settings.raysPerPoint = rays;
        }
    }
    if (mLayers) {
        mLayerSettings.raysPerPixel = rays;
        mLayers.reset();
        mLayers.emplace(mRenderer.methodContext(), mLayerSettings);
        slots[3].method = &*mLayers;
    }
    for (const Slot& s : slots) {
        if (s.method != nullptr) {
            warmUp(s);
        }
    }
}

nlohmann::json ProfileRun::buildJson() const {
    // The set and its index from whichever foveated method could be set up.
    const render::PointSetMethod* set = mNearest ? &*mNearest : mShepard ? &*mShepard : nullptr;
    const bool table = mShepard.has_value();
    return {{"point_set_ms", mSetMs},
            {"point_set_from_cache", mSetCached},
            {"points", set ? nlohmann::json(set->pointSet().points().size()) : nullptr},
            {"neighbour_index_ms", nullable(set, set ? set->neighbourIndexMs() : 0.0)},
            {"neighbour_index_mb", nullable(set, set ? set->neighbourIndexMb() : 0.0)},
            {"knn_table_k", kShepardK},
            {"knn_table_ms", nullable(table, table ? mShepard->knnTablePrepared().ms : 0.0)},
            {"knn_table_mb", nullable(table, table ? mShepard->knnTablePrepared().mb : 0.0)}};
}

nlohmann::json ProfileRun::run() {
    const auto start = Clock::now();
    foveation::PointSetParams params;
    params.display = mHmd.pointSetProfile;
    {
        progress::Step step("generating the point set", 1000);
        const foveation::CachedPointSet set =
            foveation::loadOrGenerate(mCache, params, [&](double f) { (void)step.reach(f); });
        mSetMs = set.seconds * 1e3;
        mSetCached = set.fromCache;
    }
    std::vector<Slot> slots = {{"reference", nullptr, false, 1},
                               {"nn", nullptr, true, 1},
                               {"msm", nullptr, true, 1},
                               {"layers", nullptr, false, 2}};
    setUpAll(slots, params);
    nlohmann::json rows = nlohmann::json::array();
    for (const uint32_t rays : kRays) {
        if (rays != kRays.front()) {
            setRays(rays, slots);
        }
        const std::vector<Row> measured = measure(rays, slots);
        for (std::size_t m = 0; m < slots.size(); ++m) {
            rows.push_back(rowJson(measured[m], slots[m], measured.front()));
        }
    }
    return {{"profile", mHmd.name},
            {"eye", {mHmd.eyeWidth, mHmd.eyeHeight}},
            {"pixels_per_eye", static_cast<double>(mHmd.eyeWidth) * mHmd.eyeHeight},
            {"viewing_distance", mHmd.pointSetProfile.viewingDistance},
            {"build", buildJson()},
            {"rows", rows},
            {"peak_rss_mb", peakRssMb()},
            {"wall_s", secondsSince(start)}};
}

// A figure, or NaN (printed "nan") where it is null: not measured.
double num(const nlohmann::json& j) {
    return j.is_number() ? j.get<double>() : std::nan("");
}

void printProfile(const nlohmann::json& p) {
    const auto& b = p["build"];
    std::printf("%s, left eye %ux%u (%.2f Mpx): %.0f points; set %.0f ms (%s), neighbour index "
                "%.0f ms, k-NN table (k=%u) %.0f ms, %.0f MB; peak RSS %.0f MB; %.0f s\n",
                p["profile"].get<std::string>().c_str(), p["eye"][0].get<uint32_t>(),
                p["eye"][1].get<uint32_t>(), p["pixels_per_eye"].get<double>() / 1e6,
                num(b["points"]), b["point_set_ms"].get<double>(),
                b["point_set_from_cache"].get<bool>() ? "loaded" : "generated",
                num(b["neighbour_index_ms"]), b["knn_table_k"].get<uint32_t>(),
                num(b["knn_table_ms"]), num(b["knn_table_mb"]), p["peak_rss_mb"].get<double>(),
                p["wall_s"].get<double>());
    std::printf("  %-9s %4s %10s %11s %9s %9s %9s %9s %6s %9s %9s\n", "method", "rays", "points",
                "rays/frame", "ray ratio", "GPU ms", "wall ms", "time rat.", "eff.", "method MB",
                "images MB");
    for (const auto& r : p["rows"]) {
        if (r.contains("error")) {
            std::printf("  %-9s %4u left out: %s\n", r["method"].get<std::string>().c_str(),
                        r["rays_per_sample"].get<uint32_t>(),
                        r["error"].get<std::string>().c_str());
            continue;
        }
        std::printf("  %-9s %4u %10.0f %11.0f %9.2f %9.1f %9.1f %9.2f %6.2f %9.0f %9.0f\n",
                    r["method"].get<std::string>().c_str(), r["rays_per_sample"].get<uint32_t>(),
                    r["points"].get<double>(), r["rays"].get<double>(),
                    r["ray_ratio"].get<double>(), r["gpu_ms"].get<double>(),
                    r["wall_ms"].get<double>(), r["time_ratio"].get<double>(),
                    r["efficiency"].get<double>(), r["method_mb"].get<double>(),
                    r["images_mb"].get<double>());
    }
    std::fflush(stdout);
}

// Time ratio and ray ratio against pixels per eye, one line per method and ray count, one point
// per profile; the two plots one above the other.
nlohmann::json writePlot(const std::string& path, const nlohmann::json& profiles) {
    std::map<std::string, std::vector<std::array<double, 3>>> byCase; // x, time, rays
    std::vector<std::string> names;
    for (const auto& p : profiles) {
        if (!p.contains("rows")) {
            continue; // failed
        }
        for (const auto& r : p["rows"]) {
            if (r["method"] == "reference" || r.contains("error")) {
                continue;
            }
            const auto rays = r["rays_per_sample"].get<uint32_t>();
            const std::string name = r["method"].get<std::string>() + ", " + std::to_string(rays) +
                                     (rays == 1 ? " ray" : " rays");
            if (!byCase.contains(name)) {
                names.push_back(name);
            }
            byCase[name].push_back({p["pixels_per_eye"].get<double>(),
                                    r["time_ratio"].get<double>(), r["ray_ratio"].get<double>()});
        }
    }
    std::array<std::vector<std::vector<std::pair<double, double>>>, 2> series;
    for (const std::string& n : names) {
        auto points = byCase[n];
        std::stable_sort(points.begin(), points.end(),
                         [](const auto& a, const auto& b) { return a[0] < b[0]; });
        for (std::size_t k = 0; k < 2; ++k) {
            series[k].emplace_back();
            for (const auto& pt : points) {
                series[k].back().emplace_back(pt[0], pt[k + 1]);
            }
        }
    }
    const std::string x = "pixels per eye (log scale)";
    const quality::RgbaImage time =
        curvesImage(series[0], names,
                    {"time ratio: reference GPU time / method's", "time ratio", x, "%.2f", true});
    const quality::RgbaImage rays = curvesImage(
        series[1], names, {"ray ratio: reference rays / method's", "ray ratio", x, "%.2f", true});
    quality::RgbaImage both{time.width, time.height + rays.height, time.pixels};
    both.pixels.insert(both.pixels.end(), rays.pixels.begin(), rays.pixels.end());
    image::writePngAtomic(path, both.width, both.height, both.pixels);
    nlohmann::json legend = nlohmann::json::array();
    for (std::size_t i = 0; i < names.size(); ++i) {
        legend.push_back({{"name", names[i]}, {"colour", seriesColourHex(i)}});
    }
    return {{"file", path}, {"series", legend}};
}

// A cache folder of its own, removed at the end: every set is generated.
class TemporaryCache {
public:
    TemporaryCache()
        : mPath(std::filesystem::temp_directory_path() /
                ("gazetrace-scale-" + std::to_string(::getpid()))) {
        std::filesystem::create_directories(mPath);
    }
    ~TemporaryCache() {
        std::error_code ec;
        std::filesystem::remove_all(mPath, ec);
    }
    TemporaryCache(const TemporaryCache&) = delete;
    TemporaryCache& operator=(const TemporaryCache&) = delete;
    [[nodiscard]] const std::filesystem::path& path() const noexcept { return mPath; }

private:
    std::filesystem::path mPath;
};

} // namespace

std::string scalePlotPath(const ScaleBenchOptions& o) {
    if (!o.plot.empty()) {
        return o.plot;
    }
    if (o.common.json.empty()) {
        return {};
    }
    std::filesystem::path p(o.common.json);
    p.replace_extension(".png");
    if (p == std::filesystem::path(o.common.json)) {
        p = std::filesystem::path(o.common.json).replace_extension().string() + "_plot.png";
    }
    return p.string();
}

nlohmann::json runScaleBench(const ScaleBenchOptions& o) {
    if (o.frames < 1) {
        throw ArgumentError("--frames: at least 1");
    }
    const std::vector<display::HmdProfile> hmds = profilesOf(o);
    std::optional<TemporaryCache> fresh;
    if (o.generateSets) {
        fresh.emplace();
    }
    const std::filesystem::path cache = fresh ? fresh->path()
                                        : o.common.cacheDir.empty()
                                            ? defaultCacheDir()
                                            : std::filesystem::path(o.common.cacheDir);
    const auto start = Clock::now();
    nlohmann::json profiles = nlohmann::json::array();
    std::string device, deviceType, failed;
    for (const display::HmdProfile& hmd : hmds) {
        // A profile the device or memory cannot hold (a table past a texel-buffer limit) is
        // reported and the others still run; a stop request (not a gt::Error) ends the run.
        // Profiles run smallest first, so a failure is most likely a large profile's own.
        try {
            ProfileRun run(o, hmd, cache);
            if (device.empty()) {
                device = run.renderer().context().deviceName();
                deviceType = run.renderer().context().deviceDescription();
                std::printf("gazetrace bench --suite scale on %s, %s, %u timed frame(s) per "
                            "case:\n",
                            deviceType.c_str(), o.common.scene.c_str(), o.frames);
            }
            profiles.push_back(run.run());
            printProfile(profiles.back());
            for (const auto& r : profiles.back()["rows"]) {
                if (r.contains("error") && r["rays_per_sample"] == kRays.front()) {
                    failed += (failed.empty() ? "" : ", ") + hmd.name + " " +
                              r["method"].get<std::string>();
                }
            }
        } catch (const std::exception& e) {
            // The first profile failing is the scene's or the device's problem, not its own.
            if (!outOfReach(e) || profiles.empty()) {
                throw;
            }
            std::fprintf(stderr, "gazetrace: %s: %s\n", hmd.name.c_str(), e.what());
            profiles.push_back(
                {{"profile", hmd.name},
                 {"eye", {hmd.eyeWidth, hmd.eyeHeight}},
                 {"pixels_per_eye", static_cast<double>(hmd.eyeWidth) * hmd.eyeHeight},
                 {"error", e.what()}});
            failed += (failed.empty() ? "" : ", ") + hmd.name;
        }
    }
    nlohmann::json result = {{"suite", "scale"},
                             {"device", device},
                             {"device_type", deviceType},
                             {"scene", o.common.scene},
                             {"gaze", "straight ahead"},
                             {"reconstruction", "gazetrace"},
                             {"frames", o.frames},
                             {"profiles", profiles},
                             {"wall_s", secondsSince(start)},
                             {"integrator", integratorJson(o.common.integrator)}};
    if (const std::string plot = scalePlotPath(o); !plot.empty()) {
        result["plot"] = writePlot(plot, profiles);
    }
    if (!o.common.json.empty()) {
        writeJsonFile(o.common.json, result);
    }
    std::printf("%zu profile(s) in %.0f s\n", profiles.size(), result["wall_s"].get<double>());
    if (!failed.empty()) {
        throw Error("bench --suite scale: " + failed + " failed (the others are measured" +
                    (o.common.json.empty() ? "" : " in " + o.common.json) + ")");
    }
    return result;
}

} // namespace gt::app
