#include "render_command.hpp"

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "core/log.hpp"
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

// Builds and runs one reference frame: trace -> tonemap -> readback.
Frame renderFrame(vk::Context& ctx, rg::TransientPool& pool, const passes::ReferencePass& reference,
                  const passes::TonemapPass& tonemap, const trace::GpuScene& gpuScene,
                  const scene::Scene& scene, uint32_t w, uint32_t h, uint32_t spp, uint32_t seed,
                  bool wantDot) {
    vk::Buffer host(ctx, {static_cast<VkDeviceSize>(w) * h * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                          vk::MemoryUsage::Readback, "readback.frame"});
    rg::RenderGraph graph(w, h);
    const rg::BufferId hostId = graph.importBuffer(
        "frame.host", {host.handle(), host.size(), std::nullopt, rg::Access::HostRead});
    const rg::TextureId radiance = reference.add(graph, gpuScene, scene.camera, {spp, seed});
    const rg::TextureId ldr = tonemap.add(graph, radiance, scene.exposure);
    passes::addReadbackPass(graph, "frame", ldr, hostId);
    const rg::CompiledGraph compiled = graph.compile();
    Frame f;
    if (wantDot) f.dot = graph.toDot(compiled);
    f.timings = graph.execute(compiled, pool);
    f.pixels.resize(host.size());
    host.download(std::as_writable_bytes(std::span(f.pixels)));
    return f;
}
} // namespace

nlohmann::json runRender(const RenderOptions& o) {
    if (o.method != "reference") {
        throw ArgumentError("--method: '" + o.method + "' is not available (known: reference)");
    }
    if (o.out.empty()) throw ArgumentError("--out: empty path");
    const std::filesystem::path outPath(o.out);
    {
        // Fail before any work when the PNG could not be written anyway.
        const std::filesystem::path dir =
            outPath.parent_path().empty() ? "." : outPath.parent_path();
        std::error_code ec;
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

    const char* env = std::getenv("GAZETRACE_DEVICE");
    vk::Context ctx({.validation = o.validate,
                     .synchronizationValidation = o.validate,
                     .deviceOverride = env ? env : ""});
    const trace::GpuScene gpuScene(ctx, scene, bvh);
    const passes::ReferencePass reference(ctx);
    const passes::TonemapPass tonemap(ctx);
    rg::TransientPool pool(ctx);
    {
        // Warm-up: lavapipe compiles shaders at their first dispatch, which would otherwise be
        // counted in the timed frame (docs/LAVAPIPE.md).
        rg::TransientPool warmPool(ctx);
        (void)renderFrame(ctx, warmPool, reference, tonemap, gpuScene, scene, 16, 16, 1, o.seed,
                          false);
    }
    const auto t2 = Clock::now();
    Frame frame = renderFrame(ctx, pool, reference, tonemap, gpuScene, scene, o.width, o.height,
                              o.spp, o.seed, !o.graphDot.empty());
    const double totalMs = msSince(t2);

    if (!o.graphDot.empty()) {
        const std::filesystem::path dotPath(o.graphDot);
        const std::filesystem::path tmp = dotPath.string() + ".tmp";
        {
            std::ofstream dot(tmp);
            dot << frame.dot;
            if (!dot) throw Error("cannot write " + o.graphDot);
        }
        std::filesystem::rename(tmp, dotPath);
    }
    image::writePngAtomic(outPath, o.width, o.height, frame.pixels);
    if (ctx.validationErrors() > 0) {
        throw Error(std::to_string(ctx.validationErrors()) + " Vulkan validation error(s)");
    }

    nlohmann::json gpu = nlohmann::json::object();
    for (const auto& p : frame.timings.passes)
        gpu[p.name] = p.gpuMs;
    const uint64_t rays = static_cast<uint64_t>(o.width) * o.height * o.spp;
    return {{"device", ctx.deviceName()},
            {"device_type", ctx.deviceDescription()},
            {"scene", o.scene},
            {"triangles", scene.triangleCount()},
            {"width", o.width},
            {"height", o.height},
            {"method", o.method},
            {"spp", o.spp},
            {"rays", rays},
            {"gpu_ms", gpu},
            {"gpu_total_ms", frame.timings.gpuMs},
            {"total_ms", totalMs},
            {"rays_per_second", totalMs > 0.0 ? static_cast<double>(rays) / (totalMs * 1e-3) : 0.0},
            {"load_ms", loadMs},
            {"bvh_ms", bvhMs},
            {"output", outPath.string()}};
}

} // namespace gt::app
