// The compute tracer's two-level part (kDynamic in trace.glsl) against its CPU reference,
// scene::DynamicGeometry: first-hit distances of a rig with rotated and scaled rigid instances
// and a morphed (deforming) one inside the static Cornell box, at one pose and after the pose
// moves; an instance shades as the same mesh baked into the static tree; static geometry
// renders byte-identically whether or not the two-level code runs; and the renderer poses the
// shipped animated sample through its frame ring (validation on).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.hpp"
#include "full_resolution.hpp"
#include "output_target.hpp"
#include "readback/readback.hpp"
#include "reference/reference.hpp"
#include "render_graph/render_graph.hpp"
#include "renderer.hpp"
#include "scene/builtin_scenes.hpp"
#include "scene/bvh.hpp"
#include "scene/dynamic_geometry.hpp"
#include "support/gpu_test_context.hpp"
#include "trace/cpu_tracer.hpp"
#include "trace/gpu_scene.hpp"
#include "vk/resources.hpp"

namespace gt {
namespace {

constexpr uint32_t kWidth = 64, kHeight = 48, kSeed = 7;

// An axis-aligned unit cube about the origin, 12 triangles with face normals, material 0.
scene::RigMesh cubeMesh() {
    scene::RigMesh m;
    m.name = "cube";
    const glm::vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int a = 0; a < 3; ++a) {
        for (float side : {-1.0f, 1.0f}) {
            const glm::vec3 n = side * axes[a];
            const glm::vec3 u = axes[(a + 1) % 3] * side, v = axes[(a + 2) % 3];
            const glm::vec3 c = 0.5f * n;
            const glm::vec3 p[4] = {c - 0.5f * u - 0.5f * v, c + 0.5f * u - 0.5f * v,
                                    c + 0.5f * u + 0.5f * v, c - 0.5f * u + 0.5f * v};
            for (const int i : {0, 1, 2, 0, 2, 3}) {
                m.vertices.push_back({p[i], n, {0.0f, 0.0f}});
            }
            m.triangleMaterial.insert(m.triangleMaterial.end(), 2, 0u);
        }
    }
    return m;
}

// A 4x4-quad sheet facing +Z, 1 wide and high, whose one morph target bulges its middle
// towards +Z (glTF 2.0, 3.7.2.2: position += weight * displacement).
scene::RigMesh sheetMesh() {
    scene::RigMesh m;
    m.name = "sheet";
    scene::MorphTarget bulge;
    constexpr int kQuads = 4;
    auto corner = [](int i, int j) {
        return glm::vec3(static_cast<float>(i) / kQuads - 0.5f,
                         static_cast<float>(j) / kQuads - 0.5f, 0.0f);
    };
    for (int j = 0; j < kQuads; ++j) {
        for (int i = 0; i < kQuads; ++i) {
            const glm::vec3 p[4] = {corner(i, j), corner(i + 1, j), corner(i + 1, j + 1),
                                    corner(i, j + 1)};
            for (const int k : {0, 1, 2, 0, 2, 3}) {
                m.vertices.push_back({p[k], {0.0f, 0.0f, 1.0f}, {0.0f, 0.0f}});
                const float r = glm::length(glm::vec2(p[k]));
                bulge.positions.emplace_back(0.0f, 0.0f, 0.6f * std::max(0.0f, 0.5f - r));
            }
            m.triangleMaterial.insert(m.triangleMaterial.end(), 2, 0u);
        }
    }
    m.targets.push_back(std::move(bulge));
    return m;
}

scene::RigNode trsNode(const std::string& name, glm::vec3 t, glm::quat r, glm::vec3 s) {
    scene::RigNode n;
    n.name = name;
    n.rest.translation = t;
    n.rest.rotation = r;
    n.rest.scale = s;
    return n;
}

// Node 1 slides along -X from t = 0 to 1 (LINEAR); the sheet's morph weight goes 0.2 -> 1.
scene::Animation slideAndBulge() {
    scene::Animation a;
    a.name = "slide";
    scene::AnimationSampler slide;
    slide.times = {0.0f, 1.0f};
    slide.values = {0.45f, 1.2f, 0.3f, -0.45f, 1.2f, 0.3f};
    slide.components = 3;
    scene::AnimationSampler bulge;
    bulge.times = {0.0f, 1.0f};
    bulge.values = {0.2f, 1.0f};
    bulge.components = 1;
    a.samplers = {slide, bulge};
    a.channels = {{0, 1, scene::AnimatedPath::Translation}, {1, 2, scene::AnimatedPath::Weights}};
    a.duration = 1.0f;
    return a;
}

// Two rigid instances of one cube (rotated and non-uniformly scaled; sliding) and a morphed
// sheet, inside the Cornell box's volume.
std::shared_ptr<scene::Rig> makeRig() {
    auto rig = std::make_shared<scene::Rig>();
    rig->meshes = {cubeMesh(), sheetMesh()};
    rig->nodes.push_back(
        trsNode("tilted", {-0.35f, 1.45f, 0.1f},
                glm::angleAxis(glm::radians(35.0f), glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f))),
                {0.45f, 0.3f, 0.35f}));
    rig->nodes.push_back(trsNode("slider", {0.45f, 1.2f, 0.3f},
                                 glm::angleAxis(glm::radians(20.0f), glm::vec3(0, 0, 1)),
                                 glm::vec3(0.3f)));
    rig->nodes.push_back(
        trsNode("sheet", {0.0f, 0.55f, 0.7f}, glm::quat(1, 0, 0, 0), {0.8f, 0.6f, 1.0f}));
    rig->nodes[2].weights = {0.2f};
    rig->instances = {{0, 0, -1}, {1, 0, -1}, {2, 1, -1}};
    rig->animations = {slideAndBulge()};
    rig->lightNodes = {-1};
    return rig;
}

class DynamicTraceTest : public test::GpuTest {
protected:
    // The reference pass's output (radiance, first-hit distance in alpha) of `gpu`.
    std::vector<glm::vec4> render(const trace::GpuScene& gpu, const scene::Camera& camera) {
        const passes::ReferencePass reference(ctx());
        vk::Buffer host(ctx(), {static_cast<VkDeviceSize>(kWidth) * kHeight * 16,
                                VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUsage::Readback,
                                "test.readback"});
        rg::RenderGraph graph(kWidth, kHeight);
        const rg::BufferId hostId = graph.importBuffer(
            "host", {host.handle(), host.size(), std::nullopt, rg::Access::HostRead});
        const rg::TextureId radiance = reference.add(
            graph, gpu, trace::cameraPush(camera, static_cast<float>(kWidth) / kHeight),
            {1, kSeed});
        passes::addReadbackPass(graph, "radiance", radiance, hostId);
        rg::TransientPool pool(ctx());
        graph.executeAndWait(graph.compile(), pool);
        std::vector<glm::vec4> out(static_cast<std::size_t>(kWidth) * kHeight);
        host.download(std::as_writable_bytes(std::span(out)));
        return out;
    }

    // The pixel's camera ray, as reference.comp makes it with one ray per pixel.
    static scene::Ray pixelRay(const scene::Camera& camera, uint32_t x, uint32_t y) {
        const shaders::trace::CameraPush c =
            trace::cameraPush(camera, static_cast<float>(kWidth) / kHeight);
        const glm::vec2 o = trace::sampleOffset(y * kWidth + x, 0, 1, kSeed);
        const float sx =
            (2.0f * (static_cast<float>(x) + o.x) / kWidth - 1.0f) * c.origin.w * c.forward.w +
            c.right.w;
        const float sy =
            (1.0f - 2.0f * (static_cast<float>(y) + o.y) / kHeight) * c.origin.w + c.up.w;
        const glm::vec3 dir =
            glm::normalize(glm::vec3(c.forward) + sx * glm::vec3(c.right) + sy * glm::vec3(c.up));
        return {glm::vec3(c.origin), dir};
    }

    struct CpuDepth {
        float t;
        bool instance; // the closest hit is on one of the rig's instances
    };
    // First-hit distances from the CPU: the static tree and DynamicGeometry::intersect.
    static std::vector<CpuDepth> cpuDepths(const scene::Camera& camera, const scene::Bvh& bvh,
                                           const scene::DynamicGeometry& dynamic) {
        std::vector<CpuDepth> out;
        for (uint32_t y = 0; y < kHeight; ++y) {
            for (uint32_t x = 0; x < kWidth; ++x) {
                const scene::Ray ray = pixelRay(camera, x, y);
                const float ts = bvh.intersect(ray).t;
                const scene::DynamicHit d = dynamic.intersect(ray);
                out.push_back({std::min(ts, d.t), d.valid() && d.t < ts});
            }
        }
        return out;
    }

    // Instance pixels whose GPU distance is off by more than float tolerance, and all pixels so.
    static std::pair<std::size_t, std::size_t> countMismatches(const std::vector<glm::vec4>& gpu,
                                                               const std::vector<CpuDepth>& cpu) {
        std::size_t instanceOff = 0, off = 0;
        for (std::size_t i = 0; i < cpu.size(); ++i) {
            const float g = gpu[i].w, c = cpu[i].t;
            const bool same =
                (std::isinf(g) && std::isinf(c)) || std::abs(g - c) <= 2e-4f * std::max(1.0f, c);
            if (!same) {
                ++off;
                if (cpu[i].instance) ++instanceOff;
            }
        }
        return {instanceOff, off};
    }
};

TEST_F(DynamicTraceTest, HitDistancesMatchTheCpuReferenceAsThePoseMoves) {
    scene::Scene s = scene::makeCornell();
    s.rig = makeRig();
    const scene::Bvh bvh(s);
    scene::DynamicGeometry dynamic(s.rig, {}, 0.0);
    const trace::LodGeometry level{&s, &bvh};
    trace::GpuScene gpu(ctx(), std::span(&level, 1), dynamic, 2);
    ASSERT_TRUE(gpu.dynamic());

    const std::vector<CpuDepth> before = cpuDepths(s.camera, bvh, dynamic);
    const auto instancePixels = static_cast<std::size_t>(
        std::count_if(before.begin(), before.end(), [](const CpuDepth& d) { return d.instance; }));
    ASSERT_GT(instancePixels, kWidth * kHeight / 20) << "the instances fill too little";
    const std::vector<glm::vec4> gpuBefore = render(gpu, s.camera);
    auto [instanceOff, off] = countMismatches(gpuBefore, before);
    // Silhouette pixels may flip between surfaces on rounding: at most 1 % of them.
    EXPECT_LE(instanceOff, instancePixels / 100) << "of " << instancePixels << " instance pixels";
    EXPECT_LE(off, before.size() / 100) << "pixels off";

    // The slider moves, the sheet bulges: written into the second copy, as the frame ring does.
    dynamic.update(0.75);
    gpu.update(dynamic);
    gpu.prepare(1);
    const std::vector<CpuDepth> after = cpuDepths(s.camera, bvh, dynamic);
    const std::vector<glm::vec4> gpuAfter = render(gpu, s.camera);
    std::tie(instanceOff, off) = countMismatches(gpuAfter, after);
    EXPECT_LE(instanceOff, instancePixels / 100) << "after the pose moved";
    EXPECT_LE(off, after.size() / 100) << "pixels off after the pose moved";
    // Where the CPU sees the surface move, the GPU's image changes; elsewhere it does not.
    std::size_t moved = 0, followed = 0, still = 0, changedStill = 0;
    for (std::size_t i = 0; i < after.size(); ++i) {
        if (std::abs(after[i].t - before[i].t) > 1e-3f) {
            ++moved;
            if (gpuAfter[i].w != gpuBefore[i].w) ++followed;
        } else if (!after[i].instance && !before[i].instance) {
            ++still;
            if (gpuAfter[i].w != gpuBefore[i].w) ++changedStill;
        }
    }
    ASSERT_GT(moved, 50u) << "the pose did not move enough to test";
    EXPECT_GE(followed, moved * 98 / 100) << "of " << moved << " pixels that moved";
    EXPECT_EQ(changedStill, 0u) << "of " << still << " static pixels";
}

TEST_F(DynamicTraceTest, AnInstanceShadesAsItsMeshBakedIntoTheStaticTree) {
    // The same rotated, non-uniformly scaled cube once as an instance (object-space normals
    // taken to the world by the inverse transpose) and once baked into Scene::vertices.
    auto rig = std::make_shared<scene::Rig>();
    rig->meshes = {cubeMesh()};
    rig->nodes.push_back(
        trsNode("tilted", {0.1f, 1.0f, 0.2f},
                glm::angleAxis(glm::radians(40.0f), glm::normalize(glm::vec3(0.5f, 1.0f, 0.3f))),
                {0.7f, 0.35f, 0.5f}));
    rig->instances = {{0, 0, -1}};
    rig->lightNodes = {-1};
    scene::Scene moving = scene::makeCornell();
    moving.rig = rig;
    scene::DynamicGeometry dynamic(rig, {}, 0.0);
    scene::Scene baked = scene::makeCornell();
    const glm::mat4 m = dynamic.objectToWorld(0);
    const glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(m)));
    for (const scene::Vertex& v : rig->meshes[0].vertices) {
        baked.vertices.push_back({glm::vec3(m * glm::vec4(v.position, 1.0f)),
                                  glm::normalize(normalMatrix * v.normal), v.uv});
    }
    baked.triangleMaterial.insert(baked.triangleMaterial.end(),
                                  rig->meshes[0].triangleMaterial.size(), 0u);

    const scene::Bvh movingBvh(moving), bakedBvh(baked);
    const trace::LodGeometry movingLevel{&moving, &movingBvh};
    const trace::GpuScene movingGpu(ctx(), std::span(&movingLevel, 1), dynamic, 1);
    const trace::GpuScene bakedGpu(ctx(), baked, bakedBvh);
    const std::vector<glm::vec4> a = render(movingGpu, moving.camera);
    const std::vector<glm::vec4> b = render(bakedGpu, baked.camera);
    double diff = 0.0, mean = 0.0;
    std::size_t outliers = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const double d = glm::length(glm::vec3(a[i]) - glm::vec3(b[i]));
        diff += d;
        mean += glm::length(glm::vec3(b[i]));
        if (d > 0.02 * glm::length(glm::vec3(b[i])) + 1e-4) ++outliers;
    }
    EXPECT_LT(diff / mean, 0.005) << "mean relative difference";
    EXPECT_LE(outliers, a.size() / 100) << "pixels differing by more than 2 %";
}

TEST_F(DynamicTraceTest, StaticGeometryRendersByteIdenticallyThroughTheTwoLevelTracer) {
    // A rig whose only instance lies far below the box: every ray also walks the top level,
    // finds nothing, and the static image must not change by a bit.
    auto rig = std::make_shared<scene::Rig>();
    rig->meshes = {cubeMesh()};
    rig->nodes.push_back(
        trsNode("away", {0.0f, -500.0f, 0.0f}, glm::quat(1, 0, 0, 0), glm::vec3(1.0f)));
    rig->instances = {{0, 0, -1}};
    rig->lightNodes = {-1};
    scene::Scene s = scene::makeCornell();
    const scene::Bvh bvh(s);
    const trace::GpuScene still(ctx(), s, bvh);
    ASSERT_FALSE(still.dynamic());
    s.rig = rig;
    scene::DynamicGeometry dynamic(rig, {}, 0.0);
    const trace::LodGeometry level{&s, &bvh};
    const trace::GpuScene moving(ctx(), std::span(&level, 1), dynamic, 1);
    const std::vector<glm::vec4> a = render(still, s.camera);
    const std::vector<glm::vec4> b = render(moving, s.camera);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec4)), 0);
}

// The shipped sample (content/animated): a sliding box, a turning paddle, a skinned bar and a
// morphed block under an animated sun, two frames in flight.
class RendererSceneTimeTest : public ::testing::Test {
protected:
    static std::string sample() {
        return std::string(GT_SOURCE_DIR) + "/content/animated/moving_parts.gltf";
    }

    static std::vector<uint8_t> frame(render::Renderer& r, render::FullResolution& method) {
        render::View v;
        v.name = "main";
        v.camera = r.sceneCamera();
        v.width = 96;
        v.height = 54;
        v.gaze = {48.0f, 27.0f};
        v.method = &method;
        v.post.taa = false;
        render::ReadbackTarget readback(r.context());
        render::OutputTarget* target = &readback;
        (void)r.renderFrame(std::span(&v, 1), std::span(&target, 1));
        return readback.takePixels();
    }
};

TEST_F(RendererSceneTimeTest, PosesEveryFrameCopyAndGoesBackInTimeWithoutMotion) {
    render::Renderer r({.scene = sample(), .validate = true, .framesInFlight = 2});
    const uint32_t errorsBefore = r.context().validationErrors();
    ASSERT_TRUE(r.animated());
    ASSERT_NE(r.dynamicGeometry(), nullptr);
    render::FullResolution method(r.methodContext(), {1, 3});
    r.setSceneTime(0.0);
    const std::vector<uint8_t> at0 = frame(r, method);
    r.setSceneTime(0.5);
    const std::vector<uint8_t> atHalf = frame(r, method);
    EXPECT_TRUE(at0 != atHalf) << "the scene did not move in half a second";
    // The same instant again lands in the ring's other copy, which must hold it too.
    EXPECT_TRUE(frame(r, method) == atHalf) << "the first frame after the pose moved";
    EXPECT_TRUE(frame(r, method) == atHalf) << "the second frame after the pose moved";
    r.setSceneTime(0.0); // back in time: posed afresh
    EXPECT_TRUE(frame(r, method) == at0) << "back at the start";
    EXPECT_EQ(r.context().validationErrors(), errorsBefore)
        << (r.context().validationMessages().empty() ? std::string()
                                                     : r.context().validationMessages().back());
}

// The sample with its camera turning as the paddle does (its rotation sampler, 1).
std::string withTurningCamera(const std::string& sample) {
    std::ifstream in(sample);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string channels = "\"channels\": [";
    const std::size_t at = text.find(channels);
    if (at == std::string::npos) return {};
    text.insert(at + channels.size(),
                R"({"sampler": 1, "target": {"node": 8, "path": "rotation"}},)");
    const std::filesystem::path out = test::tempDir("turning_camera") / "turning_camera.gltf";
    std::ofstream(out) << text;
    return out.string();
}

TEST_F(RendererSceneTimeTest, CameraFollowsItsNodeAndAnUnknownAnimationFailsInOneLine) {
    const std::string file = withTurningCamera(sample());
    ASSERT_FALSE(file.empty()) << "the sample has no animation channels";
    render::Renderer r({.scene = file});
    const scene::DynamicGeometry& d = *r.dynamicGeometry();
    ASSERT_GE(d.rig().cameraNode, 0) << "the loader does not see the camera animated";
    const auto cameraNode = static_cast<std::size_t>(d.rig().cameraNode);
    for (const double t : {0.5, 1.5}) {
        r.setSceneTime(t);
        // glTF cameras look down their node's -Z with +Y up (glTF 2.0, 3.10.1).
        const glm::mat4& world = d.pose().world[cameraNode];
        const scene::Camera c = r.sceneCamera();
        EXPECT_LT(glm::length(c.position - glm::vec3(world[3])), 1e-5f) << t;
        EXPECT_LT(glm::length(c.forward + glm::normalize(glm::vec3(world[2]))), 1e-5f) << t;
        EXPECT_LT(glm::length(c.up - glm::normalize(glm::vec3(world[1]))), 1e-5f) << t;
    }
    EXPECT_GT(glm::length(r.sceneCamera().forward - r.scene().camera.forward), 1e-3f)
        << "the camera did not turn";
    try {
        render::Renderer bad({.scene = sample(), .animation = "no_such_animation"});
        FAIL() << "an unknown animation was accepted";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("no_such_animation"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
}

} // namespace
} // namespace gt
