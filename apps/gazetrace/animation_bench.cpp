// `gazetrace bench --suite animation`: the per-frame CPU work of a scene that moves, apart from
// tracing — posing (glTF animation sampling down the hierarchy), deforming (morph targets and
// skinning), refitting the deforming bottom-level trees and rebuilding the top level — on the
// scene the per-frame target is stated for: 100 animated rigid instances and one skinned mesh
// of 10k vertices. Then the same for the shipped animated sample through the renderer, whose
// setSceneTime also writes the frame's tables.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>

#include "bench_command.hpp"
#include "option_parsing.hpp"
#include "renderer.hpp"
#include "scene/dynamic_geometry.hpp"

namespace gt::app {

namespace {

scene::AnimationSampler linearSampler(std::vector<float> times, std::vector<float> values,
                                      uint32_t components) {
    scene::AnimationSampler s;
    s.times = std::move(times);
    s.values = std::move(values);
    s.components = components;
    return s;
}

// A bar of `boxes` boxes along +y (12 triangles, 36 vertices each), skinned to `joints` joints
// spaced evenly along it, each vertex to the two nearest.
scene::RigMesh skinnedBar(uint32_t boxes, uint32_t joints) {
    scene::Scene s;
    scene::SceneBuilder b(s);
    const uint32_t mat = b.material({});
    const float h = 1.0f / static_cast<float>(boxes);
    for (uint32_t i = 0; i < boxes; ++i) {
        const float y = (static_cast<float>(i) + 0.5f) * h * static_cast<float>(joints);
        b.box(glm::scale(glm::translate(glm::mat4(1.0f), {0, y, 0}),
                         {0.2f, h * static_cast<float>(joints), 0.2f}),
              mat);
    }
    scene::RigMesh m;
    m.vertices = s.vertices;
    m.triangleMaterial.assign(s.triangleCount(), 0);
    for (const scene::Vertex& v : m.vertices) {
        const float j = std::clamp(v.position.y, 0.0f, static_cast<float>(joints - 1));
        const auto j0 = static_cast<uint32_t>(std::min(std::floor(j), float(joints - 2)));
        const float f = j - static_cast<float>(j0);
        m.joints.emplace_back(j0, j0 + 1, 0u, 0u);
        m.weights.emplace_back(1.0f - f, f, 0.0f, 0.0f);
    }
    return m;
}

// 100 cubes each sliding and turning on its own node, and a 16-joint bar of 10,080 vertices
// whose joints all swing.
std::shared_ptr<scene::Rig> benchRig() {
    auto rig = std::make_shared<scene::Rig>();
    scene::Scene cube;
    scene::SceneBuilder(cube).box(glm::mat4(1.0f), 0);
    scene::RigMesh cubeMesh;
    cubeMesh.vertices = cube.vertices;
    cubeMesh.triangleMaterial.assign(cube.triangleCount(), 0);
    constexpr uint32_t kJoints = 16;
    rig->meshes = {cubeMesh, skinnedBar(280, kJoints)};
    scene::Animation a;
    a.duration = 2.0f;
    for (uint32_t i = 0; i < 100; ++i) {
        scene::RigNode n;
        n.rest.translation = {static_cast<float>(i % 10) * 2.0f, 0.0f,
                              static_cast<float>(i / 10) * -2.0f};
        rig->nodes.push_back(n);
        rig->instances.push_back({i, 0, -1});
        const glm::vec3 p = n.rest.translation;
        a.samplers.push_back(linearSampler({0.0f, 2.0f}, {p.x, p.y, p.z, p.x, p.y + 1.0f, p.z}, 3));
        const glm::quat q = glm::angleAxis(3.0f, glm::vec3(0, 1, 0));
        a.samplers.push_back(linearSampler({0.0f, 2.0f}, {0, 0, 0, 1, q.x, q.y, q.z, q.w}, 4));
        a.channels.push_back({2 * i, i, scene::AnimatedPath::Translation});
        a.channels.push_back({2 * i + 1, i, scene::AnimatedPath::Rotation});
    }
    scene::Skin skin;
    for (uint32_t j = 0; j < kJoints; ++j) {
        scene::RigNode n;
        n.parent = j == 0 ? -1 : static_cast<int>(100 + j - 1);
        n.rest.translation = {j == 0 ? -4.0f : 0.0f, j == 0 ? 0.0f : 1.0f, 0.0f};
        rig->nodes.push_back(n);
        skin.joints.push_back(100 + j);
        skin.inverseBind.push_back(
            glm::translate(glm::mat4(1.0f), {4.0f, -static_cast<float>(j), 0.0f}));
        const glm::quat q = glm::angleAxis(0.15f, glm::vec3(0, 0, 1));
        a.samplers.push_back(linearSampler({0.0f, 2.0f}, {0, 0, 0, 1, q.x, q.y, q.z, q.w}, 4));
        a.channels.push_back(
            {static_cast<uint32_t>(a.samplers.size() - 1), 100 + j, scene::AnimatedPath::Rotation});
    }
    rig->skins = {skin};
    rig->nodes.emplace_back(); // the skinned mesh's node
    rig->instances.push_back({static_cast<uint32_t>(rig->nodes.size() - 1), 1, 0});
    rig->animations = {a};
    return rig;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

nlohmann::json rigCosts(uint32_t frames) {
    const auto rig = benchRig();
    scene::DynamicGeometry g(rig, {}, 0.0);
    std::vector<double> pose, deform, refit, rebuild, top, total;
    for (uint32_t i = 0; i < frames + 10; ++i) {
        g.update(static_cast<double>(i) / 90.0);
        if (i < 10) continue; // warm-up
        const scene::DynamicUpdateTimings& t = g.lastTimings();
        pose.push_back(t.poseMs);
        deform.push_back(t.deformMs);
        refit.push_back(t.refitMs);
        rebuild.push_back(t.rebuildMs);
        top.push_back(t.topLevelMs);
        total.push_back(t.poseMs + t.deformMs + t.refitMs + t.rebuildMs + t.topLevelMs);
    }
    const std::size_t vertices = rig->meshes[1].vertices.size();
    return {{"instances", rig->instances.size()},
            {"skinned_vertices", vertices},
            {"frames", frames},
            {"pose_ms", median(pose)},
            {"deform_ms", median(deform)},
            {"refit_ms", median(refit)},
            {"rebuild_ms", median(rebuild)},
            {"top_level_ms", median(top)},
            {"total_ms", median(total)}};
}

// The shipped sample through the renderer: setSceneTime poses, refits and writes the tables of
// the frame it poses for.
nlohmann::json rendererCosts(uint32_t frames) {
    const std::string sample = "content/animated/moving_parts.gltf";
    if (!std::filesystem::exists(sample)) {
        std::fprintf(stderr, "bench: %s not found from here: its row is left out\n",
                     sample.c_str());
        return nullptr;
    }
    render::Renderer r(
        {.scene = sample, .deviceOverride = deviceRequest(), .sceneLoad = gltfLoadOptions()});
    std::vector<double> ms;
    for (uint32_t i = 0; i < frames + 10; ++i) {
        const auto start = std::chrono::steady_clock::now();
        r.setSceneTime(static_cast<double>(i) / 90.0);
        const double t =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count();
        if (i >= 10) ms.push_back(t);
    }
    return {{"scene", sample}, {"frames", frames}, {"set_scene_time_ms", median(ms)}};
}

} // namespace

nlohmann::json runAnimationBench(const BenchOptions& o) {
    const uint32_t frames = o.quick ? 20 : 200;
    nlohmann::json result = {{"suite", "animation"}, {"rig", rigCosts(frames)}};
    result["renderer"] = rendererCosts(frames);
    const nlohmann::json& g = result["rig"];
    std::printf("animation, per frame (median of %u, CPU): 100 instances + 10,080-vertex skin\n"
                "  pose %.3f ms, deform %.3f ms, refit %.3f ms, rebuild %.3f ms, top level %.3f "
                "ms: total %.3f ms\n",
                frames, g["pose_ms"].get<double>(), g["deform_ms"].get<double>(),
                g["refit_ms"].get<double>(), g["rebuild_ms"].get<double>(),
                g["top_level_ms"].get<double>(), g["total_ms"].get<double>());
    if (!result["renderer"].is_null()) {
        std::printf("  %s: setSceneTime %.3f ms\n",
                    result["renderer"]["scene"].get<std::string>().c_str(),
                    result["renderer"]["set_scene_time_ms"].get<double>());
    }
    if (!o.json.empty()) writeJsonFile(o.json, result);
    return result;
}

} // namespace gt::app
