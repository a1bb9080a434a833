// `gazetrace bench --suite animation`: what a scene that moves costs the CPU per frame, apart
// from tracing. A built scene: 100 rigid instances of three meshes, each node translated and
// turned by its own LINEAR channels, and one skinned tube of 10,000 glTF vertices (100 rings of
// 100, 19,800 triangles) bent by a chain of 8 joints through large poses. Each frame is one
// DynamicGeometry::update at 60 Hz steps: the pose, the tube's skinning, its bottom-level refit
// (or rebuild), the top level over the instances. Google Benchmark times the updates (manual
// time, one per iteration); the phases' medians are printed and written as JSON.
//
// The suite also measures what refitting costs the tracer: the tube built at rest, bent ever
// further and refitted, against a fresh build at each bend (SAH costs, and the box and triangle
// tests of the same rays through both trees), the measurement behind
// DynamicGeometry::kRebuildSahRatio.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include <benchmark/benchmark.h>
#include <glm/gtc/matrix_transform.hpp>

#include "bench_command.hpp"
#include "bench_timing.hpp"
#include "bvh_refit/bvh_refit.hpp"
#include "scene/dynamic_geometry.hpp"
#include "stop_request.hpp"
#include "vk/context.hpp"
#include "vk/resources.hpp"

namespace gt::app {

namespace {

using Clock = std::chrono::steady_clock;

constexpr int kRigidInstances = 100;
constexpr int kTubeRings = 100;    // along the tube
constexpr int kTubeSegments = 100; // around it: 100 x 100 = 10,000 glTF vertices
constexpr int kTubeJoints = 8;
constexpr float kTubeLength = 4.0f;
constexpr double kFrameSeconds = 1.0 / 60.0;

scene::RigMesh meshOf(const scene::Scene& s) {
    scene::RigMesh m;
    m.vertices = s.vertices;
    m.triangleMaterial.assign(s.triangleCount(), 0u);
    return m;
}

// The three rigid meshes: a box (12 triangles), a cylinder (64) and a sphere (192).
std::vector<scene::RigMesh> rigidMeshes() {
    std::vector<scene::RigMesh> out;
    for (int kind = 0; kind < 3; ++kind) {
        scene::Scene s;
        scene::SceneBuilder b(s);
        const uint32_t mat = b.material({});
        if (kind == 0) b.box(glm::mat4(1.0f), mat);
        if (kind == 1) b.cylinder(glm::mat4(1.0f), mat);
        if (kind == 2) b.sphere(glm::mat4(1.0f), mat);
        out.push_back(meshOf(s));
    }
    return out;
}

// The tube along +y, radius 0.3, skinned to joints every kTubeLength / kTubeJoints: each vertex
// blends the two joints it lies between (4 weights, 2 of them zero).
scene::RigMesh skinnedTube() {
    const auto ringPoint = [](int ring, int seg) {
        const float a = 6.2831853f * static_cast<float>(seg) / kTubeSegments;
        const float y = kTubeLength * static_cast<float>(ring) / (kTubeRings - 1);
        return scene::Vertex{{0.3f * std::cos(a), y, 0.3f * std::sin(a)},
                             {std::cos(a), 0.0f, std::sin(a)},
                             {static_cast<float>(seg) / kTubeSegments, y / kTubeLength}};
    };
    scene::RigMesh m;
    for (int r = 0; r + 1 < kTubeRings; ++r) {
        for (int s = 0; s < kTubeSegments; ++s) {
            const int s1 = (s + 1) % kTubeSegments;
            const std::array<std::pair<int, int>, 6> corners{
                {{r, s}, {r + 1, s}, {r + 1, s1}, {r, s}, {r + 1, s1}, {r, s1}}};
            for (const auto& [ring, seg] : corners)
                m.vertices.push_back(ringPoint(ring, seg));
        }
    }
    m.triangleMaterial.assign(m.vertices.size() / 3, 0u);
    const float spacing = kTubeLength / kTubeJoints;
    for (const scene::Vertex& v : m.vertices) {
        const float f = std::min(v.position.y / spacing, kTubeJoints - 1.0f);
        const auto j = static_cast<uint32_t>(std::min(f, kTubeJoints - 2.0f));
        const float w = std::clamp(f - static_cast<float>(j), 0.0f, 1.0f);
        m.joints.emplace_back(j, j + 1, 0u, 0u);
        m.weights.emplace_back(1.0f - w, w, 0.0f, 0.0f);
    }
    return m;
}

scene::AnimationSampler linear(std::vector<float> times, std::vector<float> values,
                               uint32_t components) {
    scene::AnimationSampler s;
    s.times = std::move(times);
    s.values = std::move(values);
    s.components = components;
    return s;
}

void pushQuat(std::vector<float>& v, const glm::quat& q) {
    v.insert(v.end(), {q.x, q.y, q.z, q.w});
}

// Rigid node i: on a 10 x 10 grid, sliding along a small loop and turning once about its own
// axis in 4 seconds.
void animateRigid(scene::Rig& rig, scene::Animation& a, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const std::vector<float> times{0.0f, 1.0f, 2.0f, 3.0f, 4.0f};
    for (int i = 0; i < kRigidInstances; ++i) {
        scene::RigNode node;
        const glm::vec3 at{3.0f * static_cast<float>(i % 10 - 5), 0.0f,
                           3.0f * static_cast<float>(i / 10 - 5)};
        node.rest.translation = at;
        const auto nodeIndex = static_cast<uint32_t>(rig.nodes.size());
        rig.nodes.push_back(node);
        rig.instances.push_back({nodeIndex, static_cast<uint32_t>(i % 3), -1});
        std::vector<float> path, turn;
        const glm::vec3 axis = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + 1e-3f);
        for (int k = 0; k < 5; ++k) {
            const float phase = 1.5707963f * static_cast<float>(k);
            const glm::vec3 p = at + glm::vec3(std::cos(phase), 0.5f * std::sin(phase), 0.0f);
            path.insert(path.end(), {p.x, p.y, p.z});
            pushQuat(turn, glm::angleAxis(phase, axis));
        }
        const auto s = static_cast<uint32_t>(a.samplers.size());
        a.samplers.push_back(linear(times, path, 3));
        a.samplers.push_back(linear(times, turn, 4));
        a.channels.push_back({s, nodeIndex, scene::AnimatedPath::Translation});
        a.channels.push_back({s + 1, nodeIndex, scene::AnimatedPath::Rotation});
    }
}

// The tube's joint chain, each joint bending about z by up to 0.6 rad (4.8 rad along the tube)
// and back the other way, and about x by half that, out of phase.
void animateTube(scene::Rig& rig, scene::Animation& a) {
    const float spacing = kTubeLength / kTubeJoints;
    scene::Skin skin;
    const std::vector<float> times{0.0f, 1.0f, 2.0f, 3.0f, 4.0f};
    for (int j = 0; j < kTubeJoints; ++j) {
        scene::RigNode joint;
        joint.parent = j == 0 ? -1 : static_cast<int>(rig.nodes.size()) - 1;
        joint.rest.translation = j == 0 ? glm::vec3(0.0f, 0.0f, 0.0f) : glm::vec3(0, spacing, 0);
        const auto nodeIndex = static_cast<uint32_t>(rig.nodes.size());
        rig.nodes.push_back(joint);
        skin.joints.push_back(nodeIndex);
        skin.inverseBind.push_back(
            glm::translate(glm::mat4(1.0f), {0.0f, -spacing * static_cast<float>(j), 0.0f}));
        std::vector<float> turn;
        for (const float k : {0.0f, 0.6f, 0.0f, -0.6f, 0.0f})
            pushQuat(turn, glm::angleAxis(k, glm::vec3(0, 0, 1)) *
                               glm::angleAxis(0.5f * std::abs(k) - 0.15f, glm::vec3(1, 0, 0)));
        a.samplers.push_back(linear(times, turn, 4));
        a.channels.push_back({static_cast<uint32_t>(a.samplers.size() - 1), nodeIndex,
                              scene::AnimatedPath::Rotation});
    }
    rig.skins.push_back(skin);
    const auto meshNode = static_cast<uint32_t>(rig.nodes.size());
    rig.nodes.emplace_back();
    rig.instances.push_back({meshNode, 3u, 0});
}

std::shared_ptr<scene::Rig> benchRig() {
    auto rig = std::make_shared<scene::Rig>();
    rig->meshes = rigidMeshes();
    rig->meshes.push_back(skinnedTube());
    scene::Animation a;
    a.name = "everything";
    std::mt19937 rng(7);
    animateRigid(*rig, a, rng);
    animateTube(*rig, a);
    a.duration = 4.0f;
    rig->animations = {a};
    return rig;
}

struct UpdateSeries {
    std::vector<double> pose, deform, refit, rebuild, topLevel, total;
    uint32_t rebuilds = 0;
};

// Registers the per-frame update as a Google Benchmark case; its frames land in `series`.
void registerUpdate(const std::shared_ptr<const scene::Rig>& rig, int frames, int warm,
                    UpdateSeries& series) {
    benchmark::RegisterBenchmark(
        "animation/update/100_rigid+10k_vertex_skinned",
        [rig, warm, &series](benchmark::State& st) {
            throwIfStopRequested();
            scene::DynamicGeometry g(rig, {}, 0.0);
            int frame = 0;
            for (int i = 0; i < warm; ++i)
                g.update(++frame * kFrameSeconds);
            series = {};
            for (auto _ : st) {
                const auto start = Clock::now();
                g.update(++frame * kFrameSeconds);
                const double ms =
                    std::chrono::duration<double, std::milli>(Clock::now() - start).count();
                st.SetIterationTime(ms / 1000.0);
                const scene::DynamicUpdateTimings& t = g.lastTimings();
                series.pose.push_back(t.poseMs);
                series.deform.push_back(t.deformMs);
                series.refit.push_back(t.refitMs);
                series.rebuild.push_back(t.rebuildMs);
                series.topLevel.push_back(t.topLevelMs);
                series.total.push_back(ms);
                series.rebuilds += t.rebuilds;
            }
        })
        ->Iterations(frames)
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond);
}

bool slab(const scene::BvhNode& n, const scene::Ray& r, const glm::vec3& invDir, float tMax,
          float& enter) {
    const glm::vec3 t0 = (n.boundsMin - r.origin) * invDir, t1 = (n.boundsMax - r.origin) * invDir;
    const glm::vec3 lo = glm::min(t0, t1), hi = glm::max(t0, t1);
    enter = std::max(std::max(lo.x, lo.y), std::max(lo.z, r.tMin));
    return enter <= std::min(std::min(hi.x, hi.y), std::min(hi.z, tMax));
}

// The box and triangle tests per ray of Bvh::intersect's traversal (nearer child first, boxes
// beyond the closest hit skipped), counted rather than timed: the same rays through two trees
// compare exactly, whatever else the machine is running.
double testsPerRay(const scene::Bvh& bvh, const std::vector<scene::Ray>& rays) {
    const std::vector<scene::BvhNode>& nodes = bvh.nodes();
    uint64_t tests = 0;
    std::vector<uint32_t> stack;
    for (const scene::Ray& r : rays) {
        const glm::vec3 invDir = 1.0f / r.direction;
        float best = r.tMax, enter = 0.0f;
        stack.assign(1, 0u);
        ++tests; // the root box
        while (!stack.empty()) {
            const scene::BvhNode& n = nodes[stack.back()];
            stack.pop_back();
            if (!slab(n, r, invDir, best, enter)) continue;
            if (n.count > 0) {
                for (uint32_t i = n.leftFirst; i < n.leftFirst + n.count; ++i) {
                    float t, u, v;
                    if (intersectTriangle(bvh.triangles()[i], r, t, u, v)) best = std::min(best, t);
                }
                tests += n.count;
                continue;
            }
            float tl, tr;
            const bool hl = slab(nodes[n.leftFirst], r, invDir, best, tl);
            const bool hr = slab(nodes[n.leftFirst + 1], r, invDir, best, tr);
            tests += 2;
            if (hl && hr) {
                stack.push_back(tl <= tr ? n.leftFirst + 1 : n.leftFirst);
                stack.push_back(tl <= tr ? n.leftFirst : n.leftFirst + 1);
            } else if (hl || hr) {
                stack.push_back(hl ? n.leftFirst : n.leftFirst + 1);
            }
        }
    }
    return static_cast<double>(tests) / static_cast<double>(rays.size());
}

// Rays from a sphere around the tree's root box towards points inside it.
std::vector<scene::Ray> raysAt(const scene::Bvh& bvh, uint32_t count) {
    const scene::BvhNode& root = bvh.nodes().front();
    const glm::vec3 centre = 0.5f * (root.boundsMin + root.boundsMax);
    const float radius = glm::length(root.boundsMax - root.boundsMin);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::normal_distribution<float> n;
    std::vector<scene::Ray> rays;
    for (uint32_t i = 0; i < count; ++i) {
        scene::Ray r;
        r.origin = centre + radius * glm::normalize(glm::vec3(n(rng), n(rng), n(rng)) + 1e-6f);
        const glm::vec3 target =
            glm::mix(root.boundsMin, root.boundsMax, glm::vec3(u(rng), u(rng), u(rng)));
        r.direction = glm::normalize(target - r.origin);
        rays.push_back(r);
    }
    return rays;
}

// The tube built at rest, then bent by `bend` radians along its length (spread over its joints)
// and refitted, against a fresh build of the same bend.
nlohmann::json refitQuality(const scene::Rig& source, bool quick) {
    scene::Rig rig = source;
    const scene::MeshInstance tube = rig.instances.back();
    const std::vector<uint32_t>& joints = rig.skins[0].joints;
    std::vector<scene::Vertex> v;
    const scene::AnimationChoice still{scene::AnimationChoice::Kind::None, 0};
    deformInstance(rig, tube, evaluatePose(rig, still, 0.0), v);
    const scene::Bvh atRest{std::span<const scene::Vertex>(v)};
    nlohmann::json out = nlohmann::json::array();
    for (const float bend : {0.5f, 1.0f, 2.0f, 3.0f, 4.5f, 6.0f}) {
        for (const uint32_t j : joints)
            rig.nodes[j].rest.rotation =
                glm::angleAxis(bend / static_cast<float>(joints.size()), glm::vec3(0, 0, 1));
        deformInstance(rig, tube, evaluatePose(rig, still, 0.0), v);
        scene::Bvh refitted = atRest;
        const float refitCost = refitted.refit(v);
        const scene::Bvh fresh{std::span<const scene::Vertex>(v)};
        const std::vector<scene::Ray> rays = raysAt(fresh, quick ? 2000 : 20000);
        const double refitTests = testsPerRay(refitted, rays);
        const double freshTests = testsPerRay(fresh, rays);
        out.push_back({{"bend_rad", bend},
                       {"sah_refit_over_build", refitCost / atRest.stats().sahCost},
                       {"sah_refit_over_fresh", refitCost / fresh.stats().sahCost},
                       {"tests_per_ray_refit", refitTests},
                       {"tests_per_ray_fresh", freshTests},
                       {"tests_refit_over_fresh", refitTests / freshTests},
                       {"fresh_build_ms", 1000.0 * fresh.stats().seconds},
                       {"rebuilt", refitCost > scene::DynamicGeometry::kRebuildSahRatio *
                                                   atRest.stats().sahCost}});
    }
    return out;
}

// Where the tube's refit runs fastest: the bvh_refit pass (the GPU time of its timestamps, and
// the wall time of recording, submitting, waiting and reading the nodes back) against
// Bvh::refit on the same bent tube, medians over `runs`.
nlohmann::json refitPlacement(const scene::Rig& source, int runs) {
    scene::Rig rig = source;
    const scene::MeshInstance tube = rig.instances.back();
    const scene::AnimationChoice still{scene::AnimationChoice::Kind::None, 0};
    std::vector<scene::Vertex> rest, bent;
    deformInstance(rig, tube, evaluatePose(rig, still, 0.0), rest);
    for (const uint32_t j : rig.skins[0].joints)
        rig.nodes[j].rest.rotation = glm::angleAxis(0.4f, glm::vec3(0, 0, 1));
    deformInstance(rig, tube, evaluatePose(rig, still, 0.0), bent);
    const scene::Bvh atRest{std::span<const scene::Vertex>(rest)};
    scene::Bvh cpu = atRest;
    cpu.refit(bent);
    vk::ContextOptions options;
    options.announceDevice = false;
    vk::Context ctx(options);
    const passes::BvhRefitPass pass(ctx);
    const passes::BvhRefitLevels levels = passes::bvhRefitLevels(atRest.nodes());
    const auto storage = [&](std::span<const std::byte> bytes, vk::MemoryUsage memory) {
        vk::Buffer b(ctx, {bytes.size(), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, memory, "refit"});
        b.upload(bytes);
        return b;
    };
    vk::Buffer triangles =
        storage(std::as_bytes(std::span(cpu.triangles())), vk::MemoryUsage::Upload);
    vk::Buffer order = storage(std::as_bytes(std::span(levels.order)), vk::MemoryUsage::Upload);
    vk::Buffer nodes = storage(std::as_bytes(std::span(atRest.nodes())), vk::MemoryUsage::Readback);
    std::vector<scene::BvhNode> readBack(atRest.nodes().size());
    std::vector<double> gpuMs, wallMs, cpuMs;
    for (int i = 0; i < runs; ++i) {
        const auto t0 = Clock::now();
        rg::RenderGraph g(1, 1);
        const auto tri = g.importBuffer("triangles", {triangles.handle(), triangles.size()});
        const auto ord = g.importBuffer("order", {order.handle(), order.size()});
        const auto out = g.importBuffer(
            "nodes", {nodes.handle(), nodes.size(), std::nullopt, rg::Access::HostRead});
        g.sink(pass.add(g, levels, tri, ord, out), rg::Access::HostRead);
        rg::TransientPool pool(ctx);
        const rg::FrameTimings t = g.executeAndWait(g.compile(), pool);
        nodes.download(std::as_writable_bytes(std::span(readBack)));
        const auto t1 = Clock::now();
        cpu.refit(i % 2 == 0 ? rest : bent);
        const auto t2 = Clock::now();
        gpuMs.push_back(t.passes.empty() ? 0.0 : t.passes.front().gpuMs);
        wallMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        cpuMs.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
    }
    return {{"device", ctx.deviceName()},     {"runs", runs},
            {"nodes", atRest.nodes().size()}, {"levels", levels.levels()},
            {"gpu_ms", median(gpuMs)},        {"gpu_wall_ms", median(wallMs)},
            {"cpu_ms", median(cpuMs)}};
}

void printSummary(const nlohmann::json& r) {
    const nlohmann::json& m = r["median_ms"];
    std::printf("\nanimation (CPU, one thread, %d frames at 60 Hz): median ms per frame\n",
                r["frames"].get<int>());
    std::printf("  pose %.3f  deform %.3f  refit %.3f  rebuild %.3f  top level %.3f  "
                "update %.3f (target %.1f; slowest frame %.3f, %u rebuilds)\n",
                m["pose"].get<double>(), m["deform"].get<double>(), m["refit"].get<double>(),
                m["rebuild"].get<double>(), m["top_level"].get<double>(), m["update"].get<double>(),
                r["target_ms"].get<double>(), r["max_ms"]["update"].get<double>(),
                r["rebuilds"].get<uint32_t>());
    std::printf("refit against a fresh build (tube built at rest, bent):\n");
    for (const nlohmann::json& q : r["refit_quality"])
        std::printf("  bend %.1f rad: SAH %.2fx build, %.2fx fresh; rays' tests %.2fx fresh; a "
                    "fresh build %.1f ms%s\n",
                    q["bend_rad"].get<double>(), q["sah_refit_over_build"].get<double>(),
                    q["sah_refit_over_fresh"].get<double>(),
                    q["tests_refit_over_fresh"].get<double>(), q["fresh_build_ms"].get<double>(),
                    q["rebuilt"].get<bool>() ? " (rebuilt)" : "");
    const nlohmann::json& g = r["refit_gpu"];
    std::printf("tube refit (%d nodes, %d levels), median of %d: bvh_refit pass %.3f ms GPU, %.3f "
                "ms with submit and wait; Bvh::refit %.3f ms CPU\n",
                g["nodes"].get<int>(), g["levels"].get<int>(), g["runs"].get<int>(),
                g["gpu_ms"].get<double>(), g["gpu_wall_ms"].get<double>(),
                g["cpu_ms"].get<double>());
}

} // namespace

nlohmann::json runAnimationBench(const BenchOptions& options) {
    const std::shared_ptr<const scene::Rig> rig = benchRig();
    const int frames = options.quick ? 30 : 240; // 4 s of animation: one loop
    UpdateSeries series;
    registerUpdate(rig, frames, options.quick ? 5 : 60, series);
    int argc = 1;
    char arg0[] = "gazetrace";
    char* argv[] = {arg0, nullptr};
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::ClearRegisteredBenchmarks();
    std::size_t rigidTriangles = 0;
    for (std::size_t i = 0; i + 1 < rig->instances.size(); ++i)
        rigidTriangles += rig->meshes[rig->instances[i].mesh].triangleMaterial.size();
    nlohmann::json result = {
        {"suite", "animation"},
        {"scene",
         {{"rigid_instances", kRigidInstances},
          {"rigid_triangles", rigidTriangles},
          {"skinned_vertices", kTubeRings * kTubeSegments},
          {"skinned_triangles", rig->meshes.back().triangleMaterial.size()},
          {"joints", kTubeJoints}}},
        {"frames", frames},
        {"threads", 1},
        {"target_ms", 5.0},
        {"median_ms",
         {{"pose", median(series.pose)},
          {"deform", median(series.deform)},
          {"refit", median(series.refit)},
          {"rebuild", median(series.rebuild)},
          {"top_level", median(series.topLevel)},
          {"update", median(series.total)}}},
        {"max_ms",
         {{"update", series.total.empty()
                         ? 0.0
                         : *std::max_element(series.total.begin(), series.total.end())}}},
        {"rebuilds", series.rebuilds},
        {"rebuild_sah_ratio", scene::DynamicGeometry::kRebuildSahRatio},
        {"refit_quality", refitQuality(*rig, options.quick)},
        {"refit_gpu", refitPlacement(*rig, options.quick ? 10 : 100)}};
    printSummary(result);
    std::printf("%s\n", result.dump(2).c_str());
    if (!options.json.empty()) writeJsonFile(options.json, result);
    return result;
}

} // namespace gt::app
