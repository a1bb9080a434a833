#include "bench_command.hpp"
#include "bench_timing.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <span>

#include <unistd.h>

#include <benchmark/benchmark.h>

#include "atomic_write.hpp"
#include "core/error.hpp"
#include "eccentricity_layers.hpp"
#include "foveation/eccentricity_layers.hpp"
#include "frame_loop.hpp"
#include "full_resolution.hpp"
#include "layers_quality.hpp"
#include "method_choice.hpp"
#include "option_parsing.hpp"
#include "output_target.hpp"
#include "point_set_method.hpp"
#include "renderer.hpp"
#include "vk/context.hpp"

namespace gt::app {

namespace {

// The many-ray headline pairs: as many as fit in this time, at least 2 (1 with --quick).
constexpr double kHeadlinePairBudgetS = 60.0;
constexpr int kHeadlineMaxPairs = 15;

// What one bench frame measures: the GPU times per pass and the wall time.
struct Frame {
    rg::FrameTimings timings;
    double wallMs = 0.0;
};

// Foveated settings of one bench frame.
struct FoveatedSettings {
    glm::vec2 gaze{};
    render::PointSetSettings method;
    bool taa = true;
    passes::TaaSettings taaSettings;
};

// The bench's frames, each one view through the renderer, waited for (frames in flight are the
// stereo suite's subject), the result left on the GPU.
class BenchFrames {
public:
    BenchFrames(const std::string& scene, const foveation::PointSetParams& params,
                const std::filesystem::path& cache)
        : renderer(
              {.scene = scene, .deviceOverride = deviceRequest(), .sceneLoad = gltfLoadOptions()}),
          reference(renderer.methodContext()), pointSet(renderer.methodContext(), params, cache) {}

    Frame foveated(const FoveatedSettings& s) {
        render::View v = view(pointSet.pointSet().params().display.width,
                              pointSet.pointSet().params().display.height);
        pointSet.settings = s.method;
        v.method = &pointSet;
        v.gaze = s.gaze;
        v.post.taa = s.taa;
        v.post.taaSettings = s.taaSettings;
        return run(v);
    }
    Frame referenceFrame(uint32_t w, uint32_t h, uint32_t rays) {
        render::View v = view(w, h);
        reference.settings = {rays, 0};
        v.method = &reference;
        v.post.taa = false;
        return run(v);
    }

    render::Renderer renderer;
    render::FullResolution reference;
    render::PointSetMethod pointSet;

private:
    render::View view(uint32_t w, uint32_t h) const {
        render::View v;
        v.camera = renderer.scene().camera;
        v.width = w;
        v.height = h;
        v.exposure = renderer.scene().exposure;
        return v;
    }
    Frame run(const render::View& v) {
        const render::FrameResult f = renderOneFrame(renderer, v, mDiscard);
        return {f.timings.value_or(rg::FrameTimings{}), f.wallMs};
    }
    render::DiscardTarget mDiscard;
};

double passMs(const Frame& f, const std::string& name) {
    for (const auto& p : f.timings.passes) {
        if (p.name == name) {
            return p.gpuMs;
        }
    }
    return 0.0;
}

// The GPU time of a whole frame: first pass start to last pass end, every pass counted.
double frameMs(const Frame& f) {
    return f.timings.gpuMs;
}

// Guenter et al. 2012's predictions (Figure 12's model, section 4.3) for the desktop and fove
// profiles at slopes A and B: unit weights, as the paper predicts, and half-rate weights, as it
// measures.
nlohmann::json layerPredictions() {
    nlohmann::json out = nlohmann::json::array();
    for (const char* profile : {"desktop", "fove"}) {
        const foveation::LayerDisplay d =
            foveation::LayerDisplay::fromProfile(displayProfile(profile));
        for (const auto& [name, slope] :
             {std::pair{"A", foveation::kSlopeA}, std::pair{"B", foveation::kSlopeB}}) {
            const foveation::LayerPlan plan = foveation::optimiseLayers(d, {slope}, 3);
            std::vector<double> radii;
            nlohmann::json layers = nlohmann::json::array();
            for (std::size_t i = 0; i < plan.layers.size(); ++i) {
                const foveation::Layer& l = plan.layers[i];
                if (i + 1 < plan.layers.size()) radii.push_back(l.radiusDeg);
                layers.push_back(
                    {{"e_deg", l.radiusDeg}, {"s", l.samplingFactor}, {"P", l.pixels}});
            }
            const double halfRate =
                foveation::planLayers(d, {slope}, radii, foveation::halfRateWeights(3)).speedup();
            out.push_back({{"profile", profile},
                           {"slope", name},
                           {"layers", layers},
                           {"speedup", plan.speedup()},
                           {"speedup_half_rate", halfRate}});
        }
    }
    return out;
}

// Measured: `layers` against `reference` on the scene at the desktop profile (1920 x 1080), one
// ray per reference pixel and per layer pixel, gaze centred, same run and device. The middle
// and outer layers alternate frames, so each sample is the mean over two consecutive frames,
// paired with a reference frame between them (machine drift hits both alike).
nlohmann::json measureLayers(render::Renderer& renderer, int pairs) {
    const foveation::DisplayProfile desktop =
        foveation::displayProfile(foveation::DisplayModel::Desktop);
    const uint32_t w = desktop.width, h = desktop.height;
    render::FullResolution reference(renderer.methodContext(), {1, 0});
    render::DiscardTarget discard;
    render::View v;
    v.camera = renderer.scene().camera;
    v.width = w;
    v.height = h;
    v.exposure = renderer.scene().exposure;
    v.gaze = {0.5f * static_cast<float>(w), 0.5f * static_cast<float>(h)};
    v.post.taa = false; // the reference at 1 ray as rendered; the layers blend their own
    auto run = [&](render::FoveationMethod& method, uint64_t* rays = nullptr) {
        render::View view = v;
        view.method = &method;
        view.name = std::string(method.name());
        const render::FrameResult f = renderOneFrame(renderer, view, discard);
        if (rays) *rays = f.views.front().rays;
        return Frame{f.timings.value_or(rg::FrameTimings{}), f.wallMs};
    };
    nlohmann::json out = nlohmann::json::array();
    for (const auto& [name, slope] :
         {std::pair{"A", foveation::kSlopeA}, std::pair{"B", foveation::kSlopeB}}) {
        render::EccentricityLayerSettings s;
        s.slope = slope;
        s.display = desktop;
        render::EccentricityLayers layers(renderer.methodContext(), s);
        warmUp([&] { return run(reference).wallMs + run(layers).wallMs; });
        std::vector<double> refMs, layerMs, layerRays, ratios;
        std::map<std::string, std::vector<double>> passes;
        for (int i = 0; i < pairs; ++i) {
            uint64_t r1 = 0, r2 = 0;
            const Frame a = run(layers, &r1);
            const Frame ref = run(reference);
            const Frame b = run(layers, &r2);
            const double ms = 0.5 * (frameMs(a) + frameMs(b));
            refMs.push_back(frameMs(ref));
            layerMs.push_back(ms);
            layerRays.push_back(0.5 * static_cast<double>(r1 + r2));
            ratios.push_back(frameMs(ref) / ms);
            // Per pass, the mean over the two frames (a half-rate layer's pass counts half).
            std::map<std::string, double> pair;
            for (const Frame* f : {&a, &b}) {
                for (const auto& p : f->timings.passes)
                    pair[p.name] += 0.5 * p.gpuMs;
            }
            for (const auto& [pass, ms2] : pair)
                passes[pass].push_back(ms2);
        }
        const double pixels = static_cast<double>(w) * h;
        render::View probe = v;
        probe.method = &layers;
        nlohmann::json grids = nlohmann::json::array();
        for (const render::LayerGrid& g : layers.layout(probe).grids) {
            grids.push_back({{"width", g.width}, {"height", g.height}, {"s", g.pitch}});
        }
        nlohmann::json perPass = nlohmann::json::object();
        for (const auto& [pass, ms] : passes)
            perPass[pass] = median(ms);
        out.push_back({{"slope", name},
                       {"grids", grids},
                       {"reference_rays", pixels},
                       {"layers_rays_per_frame", median(layerRays)},
                       {"pixel_ratio", pixels / median(layerRays)},
                       {"reference_ms", median(refMs)},
                       {"layers_ms_per_frame", median(layerMs)},
                       {"time_ratio", median(ratios)},
                       {"layers_passes_ms_per_frame", perPass},
                       {"pairs", pairs}});
    }
    return out;
}

void printLayers(const nlohmann::json& predicted, const nlohmann::json& measured) {
    std::printf(
        "Eccentricity layers (Guenter et al. 2012), predicted P*/P with 3 layers (unit weights; "
        "half-rate weights):\n");
    for (const auto& p : predicted) {
        std::printf("  %-7s slope %s: %5.2f; %5.2f\n", p["profile"].get<std::string>().c_str(),
                    p["slope"].get<std::string>().c_str(), p["speedup"].get<double>(),
                    p["speedup_half_rate"].get<double>());
    }
    std::printf("Layers against the reference, desktop 1920x1080, 1 ray per pixel, mean of two "
                "frames (paper: 13.3x / 5.7x at A, 9.8x / 4.8x at B):\n");
    for (const auto& m : measured) {
        std::printf("  slope %s: rays %.0f vs %.0f, pixel ratio %.2f; %.1f ms vs %.1f ms, "
                    "time ratio %.2f\n",
                    m["slope"].get<std::string>().c_str(), m["layers_rays_per_frame"].get<double>(),
                    m["reference_rays"].get<double>(), m["pixel_ratio"].get<double>(),
                    m["layers_ms_per_frame"].get<double>(), m["reference_ms"].get<double>(),
                    m["time_ratio"].get<double>());
    }
}

// Foveated settings as Table 2's rows interpolate: as the thesis did
// (render::useThesisReconstruction), or with gazetrace's reconstruction (display-referred
// blending, depth- and colour-guided weights, q = 2, rays rotated per frame, adaptive TAA), with
// the TAA pass's time, so its cost stands beside the thesis's.
FoveatedSettings foveatedSettings(glm::vec2 gaze, passes::Interpolation m, uint32_t k,
                                  uint32_t rays,
                                  passes::KnnIndex knn = passes::KnnIndex::PixelTable,
                                  bool thesis = true) {
    FoveatedSettings s;
    s.gaze = gaze;
    s.method.raysPerPoint = rays;
    s.method.interpolation.method = m;
    s.method.interpolation.k = k;
    s.method.interpolation.knn = knn;
    if (thesis) {
        render::useThesisReconstruction(s.method, s.taaSettings);
    }
    s.taa = true; // every pass of the thesis's pipeline is counted
    return s;
}

// Table 2: interpolation time per method and k (GPU timestamps of the interpolate pass).
std::vector<std::pair<std::string, FoveatedSettings>> table2Rows(glm::vec2 centre) {
    auto fov = [&](passes::Interpolation m, uint32_t k, uint32_t rays,
                   passes::KnnIndex knn = passes::KnnIndex::PixelTable, bool thesis = true) {
        return foveatedSettings(centre, m, k, rays, knn, thesis);
    };
    std::vector<std::pair<std::string, FoveatedSettings>> table2 = {
        {"table2/nn", fov(passes::Interpolation::Nearest, 1, 1)}};
    for (uint32_t k : {5u, 10u, 15u, 20u}) {
        table2.push_back(
            {"table2/msm/k:" + std::to_string(k), fov(passes::Interpolation::Shepard, k, 1)});
    }
    // The same through the neighbour lists, the memory-light alternative to the table.
    for (uint32_t k : {5u, 10u, 15u, 20u}) {
        table2.push_back(
            {"table2/msm_lists/k:" + std::to_string(k),
             fov(passes::Interpolation::Shepard, k, 1, passes::KnnIndex::NeighbourLists)});
    }
    // RBF (multiquadric, c = p). Through the table: the per-pixel weights, built once, make a
    // frame one weighted sum per pixel. Through the lists: rbf_solve + interpolate each frame,
    // from per-point inverses built once. What is built once is reported beside the frame.
    for (uint32_t k : {5u, 10u, 15u, 20u}) {
        table2.push_back(
            {"table2/rbf/k:" + std::to_string(k), fov(passes::Interpolation::Rbf, k, 1)});
    }
    for (uint32_t k : {5u, 10u, 15u, 20u}) {
        table2.push_back({"table2/rbf_lists/k:" + std::to_string(k),
                          fov(passes::Interpolation::Rbf, k, 1, passes::KnnIndex::NeighbourLists)});
    }
    for (uint32_t k : {5u, 10u, 20u}) {
        table2.push_back(
            {"table2/msm_gazetrace/k:" + std::to_string(k),
             fov(passes::Interpolation::Shepard, k, 1, passes::KnnIndex::PixelTable, false)});
    }
    table2.push_back({"table2/nn_gazetrace", fov(passes::Interpolation::Nearest, 1, 1,
                                                 passes::KnnIndex::PixelTable, false)});
    return table2;
}

// The render suite: Table 1, Table 2, the headline comparison, the cost of a ray by gaze and the
// layers, measured on one renderer, with every frame's samples kept by name.
class BenchRun {
public:
    BenchRun(const BenchOptions& o, const foveation::PointSetParams& params,
             const std::filesystem::path& cache)
        : options(o), frames(o.quick ? 2 : 5), // median of >= 5 frames for Table 2
          session(o.scene, params, cache), w(params.display.width), h(params.display.height),
          centre(0.5f * static_cast<float>(w), 0.5f * static_cast<float>(h)),
          table2(table2Rows(centre)),
          rayCounts(o.quick ? std::vector<uint32_t>{1, 4} : std::vector<uint32_t>{1, 32}) {}

    void registerTable2();
    void addHeadline(uint32_t rays, int pairs, bool warm);
    void runBenchmarks();
    [[nodiscard]] nlohmann::json rayCostByGaze();
    [[nodiscard]] nlohmann::json table2Json();
    [[nodiscard]] nlohmann::json headlineJson();

    const BenchOptions& options;
    const int frames;
    BenchFrames session;
    const uint32_t w, h;
    const glm::vec2 centre;
    const std::vector<std::pair<std::string, FoveatedSettings>> table2;
    const std::vector<uint32_t> rayCounts;
    std::map<std::string, std::vector<double>> samples; // benchmark name -> GPU ms per frame
    std::map<std::string, std::vector<double>> walls;
    std::map<std::string, std::map<std::string, std::vector<double>>> passSamples;
    struct Built {
        std::optional<render::Prepared> table, rbf; // the k-NN table; RBF's weights or inverses
    };
    std::map<std::string, Built> prepared;
};

void BenchRun::registerTable2() {
    for (const auto& [name, settings] : table2) {
        benchmark::RegisterBenchmark(
            name.c_str(),
            [&, name = name, settings = settings](benchmark::State& st) {
                warmUp([&] { return session.foveated(settings).wallMs; });
                for (auto _ : st) {
                    const Frame f = session.foveated(settings);
                    // RBF through the lists includes its per-point solve.
                    const double ms = passMs(f, "interpolate") + passMs(f, "rbf_solve");
                    samples[name].push_back(ms);
                    samples[name + "/taa"].push_back(passMs(f, "taa"));
                    st.SetIterationTime(ms * 1e-3);
                }
                Built& b = prepared[name];
                if (passes::usesPixelTable(settings.method.interpolation)) {
                    b.table = session.pointSet.knnTablePrepared();
                }
                if (settings.method.interpolation.method == passes::Interpolation::Rbf) {
                    b.rbf = session.pointSet.rbfPrepared();
                }
            })
            ->UseManualTime()
            ->Iterations(frames)
            ->Unit(benchmark::kMillisecond);
    }
}

// Headline: foveated (nn, scale 1.0, centred gaze) against the reference, equal rays per point
// and per pixel, whole frames (every pass) measured in this run.
void BenchRun::addHeadline(uint32_t rays, int pairs, bool warm) {
    const std::string ref = "headline/reference/rays:" + std::to_string(rays);
    const std::string fv = "headline/foveated/rays:" + std::to_string(rays);
    // The reference and the foveated frame alternate within one benchmark, so that drift in the
    // machine's speed (±10 % between 32-ray frames on lavapipe) hits both alike.
    benchmark::RegisterBenchmark(
        ("headline/reference+foveated/rays:" + std::to_string(rays)).c_str(),
        [this, rays, ref, fv, warm](benchmark::State& st) {
            const FoveatedSettings fs =
                foveatedSettings(centre, passes::Interpolation::Nearest, 1, rays);
            if (warm) {
                warmUp([&] {
                    return session.referenceFrame(w, h, rays).wallMs + session.foveated(fs).wallMs;
                });
            }
            for (auto _ : st) {
                const Frame r = session.referenceFrame(w, h, rays);
                const Frame f = session.foveated(fs);
                for (const auto& [name, frame] : {std::pair{ref, &r}, std::pair{fv, &f}}) {
                    samples[name].push_back(frameMs(*frame));
                    walls[name].push_back(frame->wallMs);
                    for (const auto& p : frame->timings.passes) {
                        passSamples[name][p.name].push_back(p.gpuMs);
                    }
                }
                st.SetIterationTime((frameMs(r) + frameMs(f)) * 1e-3);
            }
        })
        ->UseManualTime()
        ->Iterations(pairs)
        ->Unit(benchmark::kMillisecond);
}

void BenchRun::runBenchmarks() {
    registerTable2();
    addHeadline(rayCounts.front(), frames, true);
    std::printf("gazetrace bench on %s (%s)\n", session.renderer.context().deviceName().c_str(),
                session.renderer.context().deviceDescription().c_str());
    std::fflush(stdout);
    int argc = 1;
    char arg0[] = "gazetrace";
    char* argv[] = {arg0, nullptr};
    benchmark::Initialize(&argc, argv);
    // One reporter for both runs: the library's default reporter does not survive a second
    // RunSpecifiedBenchmarks (it crashes in libbenchmark 1.7). Colour only on a terminal.
    benchmark::ConsoleReporter reporter(isatty(fileno(stdout)) != 0
                                            ? benchmark::ConsoleReporter::OO_Color
                                            : benchmark::ConsoleReporter::OO_None);
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::ClearRegisteredBenchmarks();
    // The many-ray pairs repeat as often as a fixed time allows, judged from the 1-ray pairs
    // scaled by the ray count (an overestimate: the fixed passes do not scale). On lavapipe a
    // 32-ray pair takes about 40 s, so it runs twice and the bench stays under 10 minutes; a
    // GPU finishes one in a fraction of a second and gets the full count.
    const auto wallMs = [&](const std::string& kind) {
        return median(walls["headline/" + kind + "/rays:" + std::to_string(rayCounts.front())]);
    };
    const double pairEstimateS =
        1e-3 * (wallMs("reference") + wallMs("foveated")) * static_cast<double>(rayCounts.back());
    const int minPairs = options.quick ? 1 : 2;
    const int pairs =
        std::clamp(static_cast<int>(kHeadlinePairBudgetS / std::max(pairEstimateS, 1e-6)), minPairs,
                   options.quick ? minPairs : kHeadlineMaxPairs);
    // A device slow enough to get the fewest pairs gets no warm-up pair either: one 32-ray pair
    // on lavapipe takes 40 s, far beyond any start-up effect.
    addHeadline(rayCounts.back(), pairs, pairs > minPairs);
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::ClearRegisteredBenchmarks();
}

// Why time_ratio trails ray_ratio: a ray's cost depends on what it meets, and the foveated rays
// crowd around the gaze. point_sample's GPU time per ray (1 ray per point) with the gaze at the
// centre and halfway to two opposite corners, beside the reference's average.
nlohmann::json BenchRun::rayCostByGaze() {
    nlohmann::json perRay = nlohmann::json::array();
    for (const glm::vec2 g : {centre, 0.5f * centre, 1.5f * centre}) {
        FoveatedSettings s = foveatedSettings(centre, passes::Interpolation::Nearest, 1, 1);
        s.gaze = g;
        s.taa = false;
        warmUp([&] { return session.foveated(s).wallMs; });
        std::vector<double> ms;
        for (int i = 0; i < frames; ++i) {
            ms.push_back(passMs(session.foveated(s), "point_sample"));
        }
        const auto points = static_cast<double>(session.pointSet.pointsSampled(g));
        perRay.push_back({{"gaze", {g.x, g.y}},
                          {"points_sampled", points},
                          {"point_sample_us_per_ray", 1e3 * median(ms) / points}});
    }
    return perRay;
}

nlohmann::json BenchRun::table2Json() {
    nlohmann::json table2json = nlohmann::json::array();
    for (const auto& [name, settings] : table2) {
        table2json.push_back(
            {{"method",
              settings.method.interpolation.method == passes::Interpolation::Nearest   ? "nn"
              : settings.method.interpolation.method == passes::Interpolation::Shepard ? "msm"
                                                                                       : "rbf"},
             {"k", settings.method.interpolation.k},
             {"reconstruction", settings.taaSettings.adaptive ? "gazetrace" : "thesis"},
             {"median_ms", median(samples[name])},
             {"taa_median_ms", median(samples[name + "/taa"])},
             {"frames", samples[name].size()}});
        const bool rbf = settings.method.interpolation.method == passes::Interpolation::Rbf;
        const bool table = passes::usesPixelTable(settings.method.interpolation);
        if (settings.method.interpolation.method != passes::Interpolation::Nearest) {
            table2json.back()["knn"] = table ? "table" : "lists";
        }
        const auto it = prepared.find(name);
        if (it == prepared.end()) {
            continue;
        }
        if (it->second.table) {
            table2json.back()["table_build_ms"] = it->second.table->ms;
            table2json.back()["table_mb"] = it->second.table->mb;
        }
        if (rbf && it->second.rbf) {
            table2json.back()["kernel"] =
                settings.method.interpolation.kernel == passes::RbfKernel::Gaussian
                    ? "gaussian"
                    : "multiquadric";
            // Per-pixel weights with the table, per-point inverses with the lists.
            table2json.back()["rbf_prepared"] = table ? "pixel_weights" : "inverses";
            table2json.back()["rbf_build_ms"] = it->second.rbf->ms;
            table2json.back()["rbf_mb"] = it->second.rbf->mb;
        }
    }
    return table2json;
}

// The cost of a traced ray alone, without the passes that do not scale with the rays:
// point_sample's GPU time per foveated ray against the reference trace's per pixel ray, and
// their ratio (1: a foveated ray costs what a reference ray does).
nlohmann::json traceCostPerRay(const std::map<std::string, std::vector<double>>& foveatedPasses,
                               const std::map<std::string, std::vector<double>>& referencePasses,
                               double foveatedRays, double referenceRays) {
    const auto ms = [](const std::map<std::string, std::vector<double>>& passes, const char* name) {
        const auto it = passes.find(name);
        return it == passes.end() ? 0.0 : median(it->second);
    };
    const double sample = 1e3 * ms(foveatedPasses, "point_sample") / foveatedRays;
    const double trace = 1e3 * ms(referencePasses, "reference.trace") / referenceRays;
    return {{"point_sample_us_per_ray", sample},
            {"reference_trace_us_per_ray", trace},
            {"point_sample_to_reference_trace", trace > 0.0 ? sample / trace : 0.0}};
}

nlohmann::json BenchRun::headlineJson() {
    nlohmann::json headline = nlohmann::json::array();
    const double pixels = static_cast<double>(w) * h;
    const auto sampled = static_cast<double>(session.pointSet.pointsSampled(centre));
    for (uint32_t rays : rayCounts) {
        const std::string ref = "headline/reference/rays:" + std::to_string(rays);
        const std::string fv = "headline/foveated/rays:" + std::to_string(rays);
        const double refMs = median(samples[ref]), fovMs = median(samples[fv]);
        headline.push_back({{"rays_per_pixel_and_point", rays},
                            {"reference_ms", refMs},
                            {"foveated_ms", fovMs},
                            {"reference_wall_ms", median(walls[ref])},
                            {"foveated_wall_ms", median(walls[fv])},
                            {"reference_rays", pixels * rays},
                            {"foveated_rays", sampled * rays},
                            {"ray_ratio", pixels / sampled},
                            {"reference_us_per_ray", 1e3 * refMs / (pixels * rays)},
                            {"foveated_us_per_ray", 1e3 * fovMs / (sampled * rays)},
                            {"time_ratio", fovMs > 0 ? refMs / fovMs : 0.0},
                            {"frames", samples[ref].size()}});
        headline.back()["trace_cost"] =
            traceCostPerRay(passSamples[fv], passSamples[ref], sampled * rays, pixels * rays);
        // Where each frame's time goes (median GPU ms per pass): interpolation and TAA weigh
        // most at 1 ray.
        for (const auto& [key, name] :
             {std::pair{"reference_passes_ms", ref}, std::pair{"foveated_passes_ms", fv}}) {
            nlohmann::json p = nlohmann::json::object();
            for (const auto& [pass, ms] : passSamples[name]) {
                p[pass] = median(ms);
            }
            headline.back()[key] = p;
        }
    }
    return headline;
}

void printTables(const nlohmann::json& result, std::size_t t1Total, uint32_t w, uint32_t h) {
    std::printf("\nTable 1 (fove, scale 1.0): total %zu, centred %.2f %%, corner %.2f %% "
                "(thesis 576,775; 72.86 %%; 26.68 %%)\n",
                t1Total, result["table1"]["centred_percent"].get<double>(),
                result["table1"]["corner_percent"].get<double>());
    std::printf("Table 2 (interpolation, %ux%u, median GPU ms):\n", w, h);
    for (const auto& r : result["table2"]) {
        const std::string label = r["method"].get<std::string>() +
                                  (r.contains("knn") ? "/" + r["knn"].get<std::string>() : "") +
                                  (r["reconstruction"] == "gazetrace" ? " gazetrace" : "");
        std::printf("  %-20s k=%-2u %8.2f ms  (taa %.2f ms)", label.c_str(), r["k"].get<uint32_t>(),
                    r["median_ms"].get<double>(), r["taa_median_ms"].get<double>());
        if (r.contains("table_build_ms")) {
            std::printf("   (k-NN table built once: %.0f ms, %.0f MB)",
                        r["table_build_ms"].get<double>(), r["table_mb"].get<double>());
        }
        if (r.contains("rbf_build_ms")) {
            std::printf("   (%s built once: %.0f ms, %.0f MB)",
                        r["rbf_prepared"] == "pixel_weights" ? "RBF pixel weights" : "inverses",
                        r["rbf_build_ms"].get<double>(), r["rbf_mb"].get<double>());
        }
        std::printf("\n");
    }
}

void printHeadline(const nlohmann::json& headline, const nlohmann::json& perRay) {
    std::printf("Headline (builtin market, centred gaze, scale 1.0, nn):\n");
    for (const auto& r : headline) {
        std::printf("  %3u ray(s): reference %9.1f ms, foveated %8.1f ms, ray_ratio %.2f, "
                    "time_ratio %.2f\n",
                    r["rays_per_pixel_and_point"].get<uint32_t>(), r["reference_ms"].get<double>(),
                    r["foveated_ms"].get<double>(), r["ray_ratio"].get<double>(),
                    r["time_ratio"].get<double>());
    }
    std::printf("Cost per ray, whole frame / point_sample at 1 ray (it depends on where the "
                "rays go):\n");
    // In ns: a GPU traces a ray in about a nanosecond, lavapipe in about half a microsecond.
    for (const auto& r : headline) {
        std::printf("  %3u ray(s): reference %.2f ns, foveated %.2f ns\n",
                    r["rays_per_pixel_and_point"].get<uint32_t>(),
                    1e3 * r["reference_us_per_ray"].get<double>(),
                    1e3 * r["foveated_us_per_ray"].get<double>());
    }
    for (const auto& r : headline) {
        const nlohmann::json& c = r["trace_cost"];
        std::printf("  %3u ray(s): point_sample %.2f ns, reference trace %.2f ns (%.2fx)\n",
                    r["rays_per_pixel_and_point"].get<uint32_t>(),
                    1e3 * c["point_sample_us_per_ray"].get<double>(),
                    1e3 * c["reference_trace_us_per_ray"].get<double>(),
                    c["point_sample_to_reference_trace"].get<double>());
    }
    for (const auto& r : perRay) {
        std::printf("  point_sample, gaze (%4.0f, %4.0f): %.2f ns per ray\n",
                    r["gaze"][0].get<double>(), r["gaze"][1].get<double>(),
                    1e3 * r["point_sample_us_per_ray"].get<double>());
    }
    std::printf("Foveated frame by pass (median GPU ms):\n");
    for (const auto& r : headline) {
        std::printf("  %3u ray(s):", r["rays_per_pixel_and_point"].get<uint32_t>());
        for (const auto& [pass, ms] : r["foveated_passes_ms"].items()) {
            std::printf(" %s %.2f", pass.c_str(), ms.get<double>());
        }
        std::printf("\n");
    }
}

} // namespace

nlohmann::json runBench(const BenchOptions& o) {
    if (!o.json.empty()) {
        const auto parent = std::filesystem::path(o.json).parent_path();
        std::error_code ec;
        if (!parent.empty() && !std::filesystem::is_directory(parent, ec)) {
            throw ArgumentError("--json: folder " + parent.string() + " does not exist");
        }
    }
    foveation::PointSetParams params;
    params.display = foveation::displayProfile(foveation::DisplayModel::Fove);
    BenchRun b(o, params, cacheFolder(o.cacheDir));
    BenchFrames& session = b.session;
    const foveation::PointSetStats t1 = session.pointSet.pointSet().stats(10.0f);
    b.runBenchmarks();
    const nlohmann::json perRay = b.rayCostByGaze();
    const nlohmann::json layerPredicted = layerPredictions();
    const nlohmann::json layerMeasured = measureLayers(session.renderer, b.frames);
    const nlohmann::json layerQuality =
        measureLayerQuality({.quick = o.quick, .scene = o.scene, .cacheDir = o.cacheDir});
    const nlohmann::json table2json = b.table2Json();
    const nlohmann::json headline = b.headlineJson();
    const double total = static_cast<double>(t1.total);
    nlohmann::json result = {
        {"device", session.renderer.context().deviceName()},
        {"device_type", session.renderer.context().deviceDescription()},
        {"scene", o.scene},
        {"width", b.w},
        {"height", b.h},
        {"quick", o.quick},
        {"table1",
         {{"profile", "fove"},
          {"scale", 1.0},
          {"viewing_distance", params.display.viewingDistance},
          {"total", t1.total},
          {"centred", t1.onScreenCentre},
          {"corner", t1.onScreenCorner},
          {"centred_percent", 100.0 * static_cast<double>(t1.onScreenCentre) / total},
          {"corner_percent", 100.0 * static_cast<double>(t1.onScreenCorner) / total},
          {"thesis", {{"total", 576775}, {"centred_percent", 72.86}, {"corner_percent", 26.68}}}}},
        {"table2", table2json},
        {"headline", headline},
        {"ray_cost_by_gaze", perRay},
        {"layers",
         {{"predicted", layerPredicted}, {"measured", layerMeasured}, {"quality", layerQuality}}},
        {"neighbour_index",
         {{"build_ms", session.pointSet.neighbourIndexMs()},
          {"mb", session.pointSet.neighbourIndexMb()},
          {"per_pixel_table_mb_k20", static_cast<double>(b.w) * 2 * b.h * 2 * 20 * 4 / 1e6}}}};
    printTables(result, t1.total, b.w, b.h);
    printHeadline(headline, perRay);
    printLayers(layerPredicted, layerMeasured);
    printLayerQuality(layerQuality);
    if (!o.json.empty()) {
        writeJsonFile(o.json, result);
    }
    return result;
}

nlohmann::json runLayersBench(const BenchOptions& o) {
    render::Renderer renderer(
        {.scene = o.scene, .deviceOverride = deviceRequest(), .sceneLoad = gltfLoadOptions()});
    std::printf("gazetrace bench --suite layers on %s (%s)\n",
                renderer.context().deviceName().c_str(),
                renderer.context().deviceDescription().c_str());
    const nlohmann::json predicted = layerPredictions();
    const nlohmann::json measured = measureLayers(renderer, o.quick ? 2 : 5);
    printLayers(predicted, measured);
    std::fflush(stdout);
    const nlohmann::json quality =
        measureLayerQuality({.quick = o.quick, .scene = o.scene, .cacheDir = o.cacheDir});
    printLayerQuality(quality);
    const nlohmann::json result = {
        {"device", renderer.context().deviceName()},
        {"device_type", renderer.context().deviceDescription()},
        {"scene", o.scene},
        {"layers", {{"predicted", predicted}, {"measured", measured}, {"quality", quality}}}};
    if (!o.json.empty()) writeJsonFile(o.json, result);
    return result;
}

void writeJsonFile(const std::string& path, const nlohmann::json& j) {
    io::writeFileAtomic(path, j.dump(2) + "\n");
}

} // namespace gt::app
