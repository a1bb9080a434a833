// `gazetrace bench --suite stereo`: the HMD path's frame — both eyes of fove (2 x 1280 x 1440) in
// one graph, foveated (nn, 8 rays per point, scale 1.0, TAA, lens) and full resolution (1 ray per
// pixel, TAA off, lens) — and the desktop demo's default frame (640 x 360, nn, 1 ray per point,
// scale 2.0, TAA), each with one frame in flight and with two. Per-pass GPU times (medians) and
// whole-frame wall times in steady state: the time between consecutive frames returning from
// renderFrame, which with frames in flight is the rate the loop sustains. Results are left on the
// GPU (no readback), as a window or headset would take them.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>

#include "bench_command.hpp"
#include "bench_timing.hpp"
#include "core/error.hpp"
#include "display/hmd_profile.hpp"
#include "foveation/point_set_cache.hpp"
#include "full_resolution.hpp"
#include "option_parsing.hpp"
#include "output_target.hpp"
#include "point_set_method.hpp"
#include "renderer.hpp"
#include "stereo_rig.hpp"
#include "stop_request.hpp"
#include "vk/context.hpp"

namespace gt::app {

namespace {

using Clock = std::chrono::steady_clock;

struct Series {
    std::string name;
    uint32_t framesInFlight = 1;
    std::vector<double> wallMs, gpuMs;
    std::map<std::string, std::vector<double>> passMs;
    uint64_t rays = 0;
};

// Frames until `warm` have gone by and then `frames` measured ones; GPU times arrive as frames
// finish, so the series ends with waitIdle.
template <typename MakeViews>
void measure(render::Renderer& r, Series& s, uint32_t warm, uint32_t frames, MakeViews&& make) {
    render::DiscardTarget discard;
    uint64_t firstMeasured = 0;
    auto collect = [&](const std::vector<rg::CompletedFrame>& done) {
        for (const rg::CompletedFrame& c : done) {
            if (c.number < firstMeasured || firstMeasured == 0) continue;
            s.gpuMs.push_back(c.timings.gpuMs);
            for (const auto& p : c.timings.passes)
                s.passMs[p.name].push_back(p.gpuMs);
        }
    };
    auto last = Clock::now();
    for (uint32_t i = 0; i < warm + frames; ++i) {
        throwIfStopRequested();
        const std::vector<render::View> views = make(i);
        const std::vector<render::OutputTarget*> targets(views.size(), &discard);
        const render::FrameResult f = r.renderFrame(views, targets);
        const auto now = Clock::now();
        if (i == warm) firstMeasured = f.number;
        if (i >= warm) {
            s.wallMs.push_back(std::chrono::duration<double, std::milli>(now - last).count());
            s.rays = 0;
            for (const auto& v : f.views)
                s.rays += v.rays;
        }
        last = now;
        std::vector<rg::CompletedFrame> done = r.takeCompleted();
        if (f.timings) done.push_back({f.number, *f.timings});
        collect(done);
    }
    r.waitIdle();
    collect(r.takeCompleted());
}

nlohmann::json toJson(const Series& s) {
    nlohmann::json passes = nlohmann::json::object();
    for (const auto& [name, ms] : s.passMs)
        passes[name] = median(ms);
    const double wall = median(s.wallMs);
    return {{"name", s.name},
            {"frames_in_flight", s.framesInFlight},
            {"frames", s.wallMs.size()},
            {"wall_ms", wall},
            {"fps", wall > 0.0 ? 1000.0 / wall : 0.0},
            {"gpu_ms", median(s.gpuMs)},
            {"rays", s.rays},
            {"passes_ms", passes}};
}

} // namespace

nlohmann::json runStereoBench(const BenchOptions& o) {
    const std::filesystem::path cache =
        o.cacheDir.empty() ? defaultCacheDir() : std::filesystem::path(o.cacheDir);
    const display::HmdProfile hmd = hmdProfile(o.hmd);
    std::vector<Series> all;
    std::string deviceName, deviceType;
    for (const uint32_t inFlight : {1u, 2u}) {
        render::Renderer r({.scene = o.scene,
                            .framesInFlight = inFlight,
                            .deviceOverride = deviceRequest(),
                            .sceneLoad = gltfLoadOptions()});
        deviceName = r.context().deviceName();
        deviceType = r.context().deviceDescription();
        const bool cpu = r.context().properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
        // A CPU driver takes seconds per stereo frame: fewer of them.
        const uint32_t warm = cpu ? 1 : 30, frames = o.quick ? 2 : (cpu ? 3 : 120);
        foveation::PointSetParams eyeParams;
        eyeParams.display = hmd.pointSetProfile;
        render::PointSetMethod eyes(r.methodContext(), eyeParams, cache);
        eyes.settings.raysPerPoint = o.quick ? 1 : 8;
        eyes.settings.interpolation.method = passes::Interpolation::Nearest;
        eyes.settings.integrator = parseIntegrator(o.integrator);
        eyes.settings.foveaRaysPerPoint = o.integrator.foveaRays;
        render::FullResolution reference(r.methodContext(), {1, 0, parseIntegrator(o.integrator)});
        const render::StereoRig rig(hmd, true);
        scene::Camera head = r.scene().camera;
        for (const bool foveated : {true, false}) {
            Series s;
            s.name = "stereo/" + hmd.name + (foveated ? "/foveated" : "/reference");
            s.framesInFlight = r.framesInFlight();
            render::PostSettings post;
            post.taa = foveated;
            post.denoise = parseDenoise(o.integrator);
            measure(r, s, warm, frames, [&](uint32_t) {
                render::StereoGaze g; // straight ahead
                const auto v = rig.views(
                    head, g, foveated ? static_cast<render::FoveationMethod&>(eyes) : reference,
                    post, r.scene().exposure);
                return std::vector<render::View>(v.begin(), v.end());
            });
            std::printf("  %-24s in flight %u: %9.2f ms wall, %9.2f ms GPU\n", s.name.c_str(),
                        s.framesInFlight, median(s.wallMs), median(s.gpuMs));
            all.push_back(std::move(s));
        }
        // The desktop demo's default frame.
        foveation::PointSetParams winParams;
        winParams.display = foveation::windowProfile(
            foveation::displayProfile(foveation::DisplayModel::Desktop), 640, 360);
        winParams.scale = 2.0;
        render::PointSetMethod window(r.methodContext(), winParams, cache);
        window.settings.raysPerPoint = 1;
        window.settings.interpolation.method = passes::Interpolation::Nearest;
        Series d;
        d.name = "desktop/640x360/foveated";
        d.framesInFlight = r.framesInFlight();
        measure(r, d, cpu ? 2 : 30, o.quick ? 3 : (cpu ? 20 : 300), [&](uint32_t) {
            render::View v;
            v.camera = head;
            v.width = 640;
            v.height = 360;
            v.gaze = {320.0f, 180.0f};
            v.method = &window;
            v.exposure = r.scene().exposure;
            return std::vector<render::View>{v};
        });
        std::printf("  %-24s in flight %u: %9.2f ms wall, %9.2f ms GPU\n", d.name.c_str(),
                    d.framesInFlight, median(d.wallMs), median(d.gpuMs));
        all.push_back(std::move(d));
    }
    nlohmann::json series = nlohmann::json::array();
    for (const Series& s : all)
        series.push_back(toJson(s));
    std::printf(
        "gazetrace bench --suite stereo on %s; the HMD frame budget at %.0f Hz is %.1f ms\n",
        deviceType.c_str(), hmd.refreshHz, 1000.0 / hmd.refreshHz);
    nlohmann::json result = {{"suite", "stereo"},
                             {"device", deviceName},
                             {"device_type", deviceType},
                             {"scene", o.scene},
                             {"hmd", hmd.name},
                             {"eye", {hmd.eyeWidth, hmd.eyeHeight}},
                             {"rays_per_point", o.quick ? 1 : 8},
                             {"integrator", integratorJson(o.integrator)},
                             {"frame_budget_ms", 1000.0 / hmd.refreshHz},
                             {"series", series}};
    if (!o.json.empty()) writeJsonFile(o.json, result);
    return result;
}

} // namespace gt::app
