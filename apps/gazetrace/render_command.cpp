#include "render_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>

#include "core/error.hpp"
#include "core/log.hpp"
#include "foveation/gpu_point_set.hpp"
#include "foveation/neighbour_index.hpp"
#include "foveation/point_set_cache.hpp"
#include "interpolate/interpolate.hpp"
#include "point_sample/point_sample.hpp"
#include "readback/readback.hpp"
#include "reference/reference.hpp"
#include "render_graph/render_graph.hpp"
#include "scene/bvh.hpp"
#include "scene/gltf_loader.hpp"
#include "scene/image_io.hpp"
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

struct Frame {
    rg::FrameTimings timings;
    std::vector<uint8_t> pixels;
    std::string dot;
};

using AddRadiance = std::function<rg::TextureId(rg::RenderGraph&)>;

// Builds and runs one frame: <radiance passes> -> tonemap -> readback.
Frame renderFrame(vk::Context& ctx, rg::TransientPool& pool, const passes::TonemapPass& tonemap,
                  const AddRadiance& addRadiance, float exposure, uint32_t w, uint32_t h,
                  bool wantDot) {
    vk::Buffer host(ctx, {static_cast<VkDeviceSize>(w) * h * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                          vk::MemoryUsage::Readback, "readback.frame"});
    rg::RenderGraph graph(w, h);
    const rg::BufferId hostId = graph.importBuffer(
        "frame.host", {host.handle(), host.size(), std::nullopt, rg::Access::HostRead});
    const rg::TextureId ldr = tonemap.add(graph, addRadiance(graph), exposure);
    passes::addReadbackPass(graph, "frame", ldr, hostId);
    const rg::CompiledGraph compiled = graph.compile();
    Frame f;
    if (wantDot) f.dot = graph.toDot(compiled);
    f.timings = graph.execute(compiled, pool);
    f.pixels.resize(host.size());
    host.download(std::as_writable_bytes(std::span(f.pixels)));
    return f;
}

glm::vec2 parseGaze(const std::string& text, uint32_t w, uint32_t h) {
    if (text.empty()) return {0.5f * static_cast<float>(w), 0.5f * static_cast<float>(h)};
    float x = 0, y = 0;
    char extra = 0;
    if (std::sscanf(text.c_str(), "%f,%f%c", &x, &y, &extra) != 2 || !std::isfinite(x) ||
        !std::isfinite(y)) {
        throw ArgumentError("--gaze: expected X,Y in pixels, got '" + text + "'");
    }
    if (x < 0 || y < 0 || x >= static_cast<float>(w) || y >= static_cast<float>(h)) {
        throw ArgumentError("--gaze: " + text + " is outside the " + std::to_string(w) + "x" +
                            std::to_string(h) + " screen");
    }
    return {x, y};
}

void writeText(const std::string& path, const std::string& text) {
    const std::filesystem::path p(path);
    const std::filesystem::path tmp = p.string() + ".tmp";
    {
        std::ofstream out(tmp);
        out << text;
        if (!out) throw Error("cannot write " + path);
    }
    std::filesystem::rename(tmp, p);
}

} // namespace

nlohmann::json runRender(const RenderOptions& o) {
    if (o.method != "reference" && o.method != "foveated") {
        throw ArgumentError("--method: '" + o.method +
                            "' is not available (known: reference, foveated)");
    }
    if (o.out.empty()) throw ArgumentError("--out: empty path");
    const bool foveated = o.method == "foveated";
    uint32_t width = o.width, height = o.height;
    foveation::PointSetParams psParams;
    passes::InterpolateSettings interp;
    glm::vec2 gaze{};
    if (foveated) {
        psParams.display = foveation::displayProfile(o.profile);
        psParams.scale = o.scale;
        if (o.sizeGiven &&
            (o.width != psParams.display.width || o.height != psParams.display.height)) {
            throw ArgumentError("--width/--height: the " + o.profile + " profile renders " +
                                std::to_string(psParams.display.width) + "x" +
                                std::to_string(psParams.display.height));
        }
        width = psParams.display.width;
        height = psParams.display.height;
        interp.method = passes::parseInterpolation(o.interp);
        interp.k = o.k;
        if (o.k == 0 || o.k > foveation::NeighbourIndex::kMaxNeighbours) {
            throw ArgumentError("--k must be 1..20");
        }
        gaze = parseGaze(o.gaze, width, height);
    }
    // --out: a .png file for one frame, else a folder for frame_NNNN.png.
    const std::filesystem::path outPath(o.out);
    const bool toFolder = outPath.extension() != ".png";
    if (!toFolder && o.frames > 1) throw ArgumentError("--out: give a folder for --frames > 1");
    {
        // Fail before any work when the output could not be written anyway.
        const std::filesystem::path dir = toFolder                        ? outPath
                                          : outPath.parent_path().empty() ? "."
                                                                          : outPath.parent_path();
        std::error_code ec;
        if (toFolder) std::filesystem::create_directories(dir, ec);
        if (!std::filesystem::is_directory(dir, ec)) {
            throw ArgumentError("--out: cannot write " + o.out + ": folder " + dir.string() +
                                " does not exist");
        }
    }
    const auto t0 = Clock::now();
    scene::GltfLoadReport report;
    const scene::Scene scene = scene::loadScene(o.scene, &report);
    for (const std::string& w : report.warnings)
        log::warn(o.scene + ": " + w);
    const double loadMs = msSince(t0);
    const auto t1 = Clock::now();
    const scene::Bvh bvh(scene);
    const double bvhMs = msSince(t1);

    std::optional<foveation::CachedPointSet> pointSet;
    std::optional<foveation::NeighbourIndex> neighbours;
    double pointSetMs = 0.0, neighbourMs = 0.0;
    if (foveated) {
        const auto t = Clock::now();
        pointSet = foveation::loadOrGenerate(o.cacheDir.empty() ? foveation::defaultCacheDir()
                                                                : std::filesystem::path(o.cacheDir),
                                             psParams);
        if (!pointSet->warning.empty()) log::warn(pointSet->warning);
        pointSetMs = msSince(t);
        neighbours.emplace(pointSet->set,
                           std::max(1u, std::min(o.k, foveation::NeighbourIndex::kMaxNeighbours)));
        neighbourMs = neighbours->buildSeconds() * 1e3;
    }

    const char* env = std::getenv("GAZETRACE_DEVICE");
    vk::Context ctx({.validation = o.validate,
                     .synchronizationValidation = o.validate,
                     .deviceOverride = env ? env : ""});
    const trace::GpuScene gpuScene(ctx, scene, bvh);
    const passes::ReferencePass reference(ctx);
    const passes::TonemapPass tonemap(ctx);
    std::optional<foveation::GpuPointSet> gpuPoints;
    std::optional<passes::PointSamplePass> pointSample;
    std::optional<passes::InterpolatePass> interpolate;
    if (foveated) {
        gpuPoints.emplace(ctx, pointSet->set, *neighbours);
        pointSample.emplace(ctx);
        interpolate.emplace(ctx);
    }
    auto radianceFor = [&](uint32_t frame) -> AddRadiance {
        if (!foveated) {
            return [&, frame](rg::RenderGraph& g) {
                return reference.add(g, gpuScene, scene.camera, {o.spp, o.seed + frame});
            };
        }
        return [&](rg::RenderGraph& g) {
            const rg::BufferId samples =
                pointSample->add(g, gpuScene, scene.camera, *gpuPoints, gaze, o.raysPerPoint);
            return interpolate->add(g, *gpuPoints, samples, gaze, interp);
        };
    };
    {
        // Warm-up: lavapipe compiles shaders at their first dispatch, which would otherwise be
        // counted in the timed frame (docs/LAVAPIPE.md).
        rg::TransientPool warmPool(ctx);
        (void)renderFrame(ctx, warmPool, tonemap, radianceFor(0), scene.exposure,
                          foveated ? width : 16, foveated ? height : 16, false);
    }
    rg::TransientPool pool(ctx);
    Frame frame;
    std::vector<double> frameMs;
    std::vector<std::string> outputs;
    for (uint32_t i = 0; i < o.frames; ++i) {
        const auto t2 = Clock::now();
        frame = renderFrame(ctx, pool, tonemap, radianceFor(i), scene.exposure, width, height,
                            !o.graphDot.empty() && i == 0);
        frameMs.push_back(msSince(t2));
        if (i == 0 && !o.graphDot.empty()) writeText(o.graphDot, frame.dot);
        char name[32];
        std::snprintf(name, sizeof(name), "frame_%04u.png", i);
        const std::filesystem::path file = toFolder ? outPath / name : outPath;
        image::writePngAtomic(file, width, height, frame.pixels);
        outputs.push_back(file.string());
    }
    if (ctx.validationErrors() > 0) {
        throw Error(std::to_string(ctx.validationErrors()) + " Vulkan validation error(s)");
    }

    nlohmann::json gpu = nlohmann::json::object();
    for (const auto& p : frame.timings.passes)
        gpu[p.name] = p.gpuMs;
    std::vector<double> sorted = frameMs;
    std::sort(sorted.begin(), sorted.end());
    const double totalMs = sorted[sorted.size() / 2];
    uint64_t rays = static_cast<uint64_t>(width) * height * o.spp;
    nlohmann::json j = {{"device", ctx.deviceName()},
                        {"device_type", ctx.deviceDescription()},
                        {"scene", o.scene},
                        {"triangles", scene.triangleCount()},
                        {"width", width},
                        {"height", height},
                        {"method", o.method},
                        {"gpu_ms", gpu},
                        {"gpu_total_ms", frame.timings.gpuMs},
                        {"total_ms", totalMs},
                        {"frames", o.frames},
                        {"load_ms", loadMs},
                        {"bvh_ms", bvhMs},
                        {"output", toFolder ? outPath.string() : outputs.front()}};
    if (foveated) {
        const glm::vec2 off = passes::gazeOffset(gaze, width, height);
        const std::size_t sampled =
            pointSet->set.countOnScreen(off.x + static_cast<float>(width),
                                        off.y + static_cast<float>(height), passes::kSampleMargin);
        rays = static_cast<uint64_t>(sampled) * o.raysPerPoint;
        j["points_sampled"] = sampled;
        j["points_total"] = pointSet->set.points().size();
        j["rays_per_point"] = o.raysPerPoint;
        j["interp"] = o.interp;
        j["k"] = interp.method == passes::Interpolation::Nearest ? 1u : o.k;
        j["scale"] = o.scale;
        j["profile"] = o.profile;
        j["gaze"] = {gaze.x, gaze.y};
        j["point_set_ms"] = pointSetMs;
        j["neighbour_index_ms"] = neighbourMs;
        j["neighbour_index_mb"] = static_cast<double>(neighbours->bytes()) / 1e6;
    } else {
        j["spp"] = o.spp;
    }
    j["rays"] = rays;
    j["rays_per_second"] = totalMs > 0.0 ? static_cast<double>(rays) / (totalMs * 1e-3) : 0.0;
    return j;
}

} // namespace gt::app
