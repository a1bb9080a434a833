// glTF animation, skins and morph targets as the loader reads them into Scene::rig: Khronos'
// animated samples posed at chosen instants against values worked out by hand from their
// keyframes, and small files built here whose broken animation data must be refused in one line.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "core/error.hpp"
#include "scene/animation.hpp"
#include "scene/gltf_loader.hpp"
#include "support/gltf_fixtures.hpp"
#include "support/gpu_test_context.hpp"

namespace gt::scene {
namespace {

std::filesystem::path khronos(const std::string& sample) {
    const auto content = test::sharedContent();
    if (content.empty()) return {};
    const auto p = content / ("khronos_" + sample) / (sample + ".gltf");
    return std::filesystem::exists(p) ? p : std::filesystem::path{};
}

// The rig node a channel of animation 0 with `path` targets (the samples' nodes are unnamed).
int channelNode(const Rig& rig, AnimatedPath path) {
    for (const AnimationChannel& c : rig.animations.at(0).channels) {
        if (c.path == path) return static_cast<int>(c.node);
    }
    return -1;
}

int nodeNamed(const Rig& rig, const std::string& name) {
    for (std::size_t i = 0; i < rig.nodes.size(); ++i) {
        if (rig.nodes[i].name == name) return static_cast<int>(i);
    }
    return -1;
}

void expectMatrixNear(const glm::mat4& a, const glm::mat4& b, float tolerance) {
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            EXPECT_NEAR(a[c][r], b[c][r], tolerance) << "column " << c << " row " << r;
        }
    }
}

TEST(GltfAnimation, AnimatedCubeRotatesAsItsKeysSay) {
    const auto file = khronos("AnimatedCube");
    if (file.empty()) GTEST_SKIP() << "../shared/content/khronos_AnimatedCube is absent";
    const Scene s = loadGltf(file);
    ASSERT_TRUE(s.rig);
    const Rig& rig = *s.rig;
    // The only mesh moves: nothing is left in the static triangles.
    EXPECT_EQ(s.triangleCount(), 0u);
    ASSERT_EQ(rig.instances.size(), 1u);
    EXPECT_EQ(rig.meshes[rig.instances[0].mesh].vertices.size(), 36u); // 12 triangles
    ASSERT_EQ(rig.animations.size(), 1u);
    const Animation& a = rig.animations[0];
    ASSERT_EQ(a.channels.size(), 1u);
    EXPECT_EQ(a.channels[0].path, AnimatedPath::Rotation);
    EXPECT_EQ(a.samplers[a.channels[0].sampler].interpolation, Interpolation::Linear);
    EXPECT_EQ(a.samplers[a.channels[0].sampler].times.size(), 3u);
    EXPECT_FLOAT_EQ(a.duration, 2.0f);
    // Keys at 0 s and 1 s: identity (0, 0, 0, 1) and a half turn (0, 1, 0, -4.37e-8). Their dot
    // product is negative, so glTF's slerp (Appendix C) takes the shortest arc, to the negated
    // key (0, -1, 0, 4.37e-8): at 0.5 s a quarter turn about -Y, which takes +X to +Z; at
    // 0.25 s an eighth.
    const int node = static_cast<int>(rig.instances[0].node);
    const Pose half = evaluatePose(rig, AnimationChoice{}, 0.5);
    EXPECT_NEAR(
        glm::length(glm::vec3(half.world[node] * glm::vec4(1, 0, 0, 0)) - glm::vec3(0, 0, 1)), 0.0f,
        1e-5f);
    const Pose eighth = evaluatePose(rig, AnimationChoice{}, 0.25);
    const float r = std::sqrt(0.5f);
    EXPECT_NEAR(
        glm::length(glm::vec3(eighth.world[node] * glm::vec4(1, 0, 0, 0)) - glm::vec3(r, 0, r)),
        0.0f, 1e-5f);
}

TEST(GltfAnimation, BoxAnimatedMovesOnlyItsAnimatedBranch) {
    const auto file = khronos("BoxAnimated");
    if (file.empty()) GTEST_SKIP() << "../shared/content/khronos_BoxAnimated is absent";
    const Scene s = loadGltf(file);
    ASSERT_TRUE(s.rig);
    const Rig& rig = *s.rig;
    // Node 3's mesh stands still and stays static; node 2's sits under the translated node 0.
    EXPECT_GT(s.triangleCount(), 0u);
    ASSERT_EQ(rig.instances.size(), 1u);
    EXPECT_EQ(rig.nodes.size(), 4u);
    ASSERT_EQ(rig.animations.size(), 1u);
    const Animation& a = rig.animations[0];
    ASSERT_EQ(a.channels.size(), 2u);
    EXPECT_NEAR(a.duration, 3.70833f, 1e-5f);
    for (std::size_t i = 0; i < rig.nodes.size(); ++i) {
        if (rig.nodes[i].parent >= 0) EXPECT_LT(rig.nodes[i].parent, static_cast<int>(i));
    }
    const int mover = channelNode(rig, AnimatedPath::Translation);
    ASSERT_GE(mover, 0);
    // The moving instance's node descends from the translated node.
    int up = static_cast<int>(rig.instances[0].node);
    while (up >= 0 && up != mover)
        up = rig.nodes[up].parent;
    EXPECT_EQ(up, mover);
    // Translation keys y: 0 at 0 s, 2.52 at 1.25 s and 2.5 s, 0 at 3.70833 s. At 0.625 s the box
    // is halfway up; at 3.1 s, 0.6 s into the last 1.20833 s segment, it has come down that far.
    // The rotation's first key is at 1.25 s: before it the sampler holds that key (identity).
    const Pose p = evaluatePose(rig, AnimationChoice{}, 0.625);
    expectMatrixNear(p.world[rig.instances[0].node],
                     glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.26f, 0.0f)), 1e-5f);
    const Pose late = evaluatePose(rig, AnimationChoice{}, 3.1);
    EXPECT_NEAR(late.world[mover][3].y, 2.52f * (1.0f - 0.6f / 1.20833f), 1e-4f);
}

TEST(GltfAnimation, CesiumMilkTruckWheelsTurnBetweenKeys) {
    const auto file = khronos("CesiumMilkTruck");
    if (file.empty()) GTEST_SKIP() << "../shared/content/khronos_CesiumMilkTruck is absent";
    const Scene s = loadGltf(file);
    ASSERT_TRUE(s.rig);
    const Rig& rig = *s.rig;
    EXPECT_GT(s.triangleCount(), 0u); // the body does not move
    EXPECT_EQ(rig.instances.size(), 2u);
    ASSERT_EQ(rig.animations.size(), 1u);
    EXPECT_EQ(rig.animations[0].channels.size(), 2u);
    EXPECT_FLOAT_EQ(rig.animations[0].duration, 1.25f);
    const int wheel = nodeNamed(rig, "Wheels"), axle = nodeNamed(rig, "Node");
    const int root = nodeNamed(rig, "Yup2Zup");
    ASSERT_GE(wheel, 0);
    ASSERT_EQ(rig.nodes[wheel].parent, axle);
    // Keys 1 and 2 (1/24 s apart) turn the wheel about -Y by 2 asin(0.189215) and
    // 2 asin(0.287996): halfway between them, at 0.0625 s, by the mean of the two angles.
    const float halfAngle = 0.5f * (std::asin(0.18921537f) + std::asin(0.28799587f));
    const glm::quat turn(std::cos(halfAngle), 0.0f, -std::sin(halfAngle), 0.0f);
    // Yup2Zup's rotation, then Node's translation, from the file.
    const glm::mat4 parent = glm::mat4_cast(glm::quat(0.49999997f, 0.49999997f, -0.5f, 0.5f)) *
                             glm::translate(glm::mat4(1.0f), glm::vec3(1.43267f, 0.0f, -0.427722f));
    const Pose p = evaluatePose(rig, AnimationChoice{}, 0.0625);
    expectMatrixNear(p.world[root],
                     glm::mat4_cast(glm::quat(0.49999997f, 0.49999997f, -0.5f, 0.5f)), 1e-5f);
    expectMatrixNear(p.world[wheel], parent * glm::mat4_cast(turn), 1e-4f);
}

TEST(GltfAnimation, TheShippedSampleMovesEveryKindOfPart) {
    const auto file =
        std::filesystem::path(GT_SOURCE_DIR) / "content" / "animated" / "moving_parts.gltf";
    GltfLoadReport report;
    const Scene s = loadGltf(file, &report);
    EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
    ASSERT_TRUE(s.rig);
    const Rig& rig = *s.rig;
    EXPECT_EQ(s.triangleCount(), 12u); // the floor, which stands still
    ASSERT_EQ(rig.instances.size(), 4u);
    ASSERT_EQ(rig.animations.size(), 1u);
    const Animation& a = rig.animations[0];
    EXPECT_EQ(a.channels.size(), 4u);
    EXPECT_FLOAT_EQ(a.duration, 4.0f);
    EXPECT_EQ(a.samplers[1].interpolation, Interpolation::CubicSpline);
    EXPECT_EQ(a.samplers[3].components, 1u); // one morph target
    ASSERT_EQ(rig.skins.size(), 1u);
    EXPECT_EQ(rig.cameraNode, -1); // the camera stands still
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(rig.lightNodes, std::vector<int>{-1});
    const auto instanceNamed = [&](const std::string& name) -> const MeshInstance& {
        for (const MeshInstance& i : rig.instances) {
            if (rig.nodes[i.node].name == name) return i;
        }
        ADD_FAILURE() << "no instance " << name;
        return rig.instances[0];
    };
    // 0.5 s is halfway from x = -2.5 to 2.5; the paddle's zero-tangent Hermite segment is
    // symmetric, so halfway through its first quarter turn it has turned 45 degrees about +Y.
    const Pose half = evaluatePose(rig, AnimationChoice{}, 0.5);
    EXPECT_NEAR(half.world[instanceNamed("sliding_box").node][3].x, 0.0f, 1e-5f);
    const glm::vec3 paddleX(half.world[instanceNamed("paddle").node] * glm::vec4(1, 0, 0, 0));
    EXPECT_NEAR(glm::length(paddleX - glm::vec3(std::sqrt(0.5f), 0.0f, -std::sqrt(0.5f))), 0.0f,
                1e-5f);
    // At 1 s the tip joint has turned 60 degrees about +Z around (-2, 1, -1.5): the bar's top
    // corner (-2.15, 2, -1.65), all on the tip, goes to (-2 - 0.15 c - s, 1 - 0.15 s + c, -1.65);
    // the block's morph weight is 1, its top at 0.5 + 0.9.
    const Pose one = evaluatePose(rig, AnimationChoice{}, 1.0);
    const MeshInstance& bar = instanceNamed("bending_bar");
    std::vector<Vertex> out;
    deformInstance(rig, bar, one, out);
    const std::vector<Vertex>& rest = rig.meshes[bar.mesh].vertices;
    const float c = 0.5f, sn = std::sqrt(3.0f) / 2.0f;
    bool found = false;
    for (std::size_t v = 0; v < rest.size(); ++v) {
        if (glm::length(rest[v].position - glm::vec3(-2.15f, 2.0f, -1.65f)) > 1e-5f) continue;
        found = true;
        const glm::vec3 world(instanceTransform(rig, bar, one) * glm::vec4(out[v].position, 1.0f));
        EXPECT_NEAR(
            glm::length(world - glm::vec3(-2.0f - 0.15f * c - sn, 1.0f - 0.15f * sn + c, -1.65f)),
            0.0f, 1e-4f);
    }
    EXPECT_TRUE(found);
    const MeshInstance& block = instanceNamed("rising_block");
    deformInstance(rig, block, one, out);
    float top = 0.0f;
    for (const Vertex& v : out)
        top = std::max(top, v.position.y);
    EXPECT_NEAR(top, 1.4f, 1e-5f);
}

// A glTF written here: one buffer as a base64 data: URI, accessors appended one by one.
class TinyGltf {
public:
    // Float data of `type` (SCALAR, VEC3, ...); returns the accessor index.
    int floats(const std::vector<float>& v, const std::string& type) {
        return add(v.data(), v.size() * 4, 5126, type, v.size() / components(type), false);
    }
    int bytes(const std::vector<uint8_t>& v, const std::string& type, bool normalized) {
        return add(v.data(), v.size(), 5121, type, v.size() / components(type), normalized);
    }
    int shorts(const std::vector<uint16_t>& v, const std::string& type, bool normalized) {
        return add(v.data(), v.size() * 2, 5123, type, v.size() / components(type), normalized);
    }
    // A float accessor whose elements `indices` (ubyte) are replaced by `values` (glTF 3.6.2.3).
    int sparseFloats(std::size_t count, const std::string& type,
                     const std::vector<uint8_t>& indices, const std::vector<float>& values) {
        const int iv = view(indices.data(), indices.size());
        const int vv = view(values.data(), values.size() * 4);
        mAccessors.push_back(
            R"({"componentType":5126,"type":")" + type + R"(","count":)" + std::to_string(count) +
            R"(,"sparse":{"count":)" + std::to_string(indices.size()) +
            R"(,"indices":{"bufferView":)" + std::to_string(iv) +
            R"(,"componentType":5121},"values":{"bufferView":)" + std::to_string(vv) + "}}}");
        return static_cast<int>(mAccessors.size()) - 1;
    }
    // The document: `rest` holds the other top-level members ("nodes":..., "meshes":...).
    std::filesystem::path write(const std::filesystem::path& dir, const std::string& name,
                                const std::string& rest) const {
        std::string json = R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":)" +
                           std::to_string(mBin.size()) +
                           R"(,"uri":"data:application/octet-stream;base64,)" + base64(mBin) +
                           R"("}],"bufferViews":[)" + join(mViews) + R"(],"accessors":[)" +
                           join(mAccessors) + "]," + rest + "}";
        test::writeFile(dir / name, json.data(), json.size());
        return dir / name;
    }

private:
    static std::size_t components(const std::string& type) {
        if (type == "SCALAR") return 1;
        if (type == "VEC2") return 2;
        if (type == "VEC3") return 3;
        if (type == "VEC4") return 4;
        return 16; // MAT4
    }
    int view(const void* data, std::size_t n) {
        while (mBin.size() % 4 != 0)
            mBin.push_back('\0');
        const std::size_t offset = mBin.size();
        mBin.append(static_cast<const char*>(data), n);
        mViews.push_back(R"({"buffer":0,"byteOffset":)" + std::to_string(offset) +
                         R"(,"byteLength":)" + std::to_string(n) + "}");
        return static_cast<int>(mViews.size()) - 1;
    }
    int add(const void* data, std::size_t n, int componentType, const std::string& type,
            std::size_t count, bool normalized) {
        const int v = view(data, n);
        mAccessors.push_back(R"({"bufferView":)" + std::to_string(v) + R"(,"componentType":)" +
                             std::to_string(componentType) + R"(,"type":")" + type +
                             R"(","count":)" + std::to_string(count) +
                             (normalized ? R"(,"normalized":true})" : "}"));
        return static_cast<int>(mAccessors.size()) - 1;
    }
    static std::string join(const std::vector<std::string>& parts) {
        std::string out;
        for (const std::string& p : parts)
            out += (out.empty() ? "" : ",") + p;
        return out;
    }
    static std::string base64(const std::string& in) {
        static const char* table =
            "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        std::string out;
        for (std::size_t i = 0; i < in.size(); i += 3) {
            uint32_t n = static_cast<uint8_t>(in[i]) << 16;
            if (i + 1 < in.size()) n |= static_cast<uint8_t>(in[i + 1]) << 8;
            if (i + 2 < in.size()) n |= static_cast<uint8_t>(in[i + 2]);
            const std::size_t left = in.size() - i;
            out += table[(n >> 18) & 63];
            out += table[(n >> 12) & 63];
            out += left > 1 ? table[(n >> 6) & 63] : '=';
            out += left > 2 ? table[n & 63] : '=';
        }
        return out;
    }
    std::string mBin;
    std::vector<std::string> mViews, mAccessors;
};

using test::loadError;

// A triangle on node 1 under node 0, node 0 translated by animation 0's sampler 0.
struct AnimatedTriangle {
    TinyGltf g;
    int positions = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3");

    std::string document(int input, int output, const std::string& interpolation = "LINEAR",
                         const std::string& channel =
                             R"("sampler":0,"target":{"node":0,"path":"translation"})") const {
        return R"("scenes":[{"nodes":[0]}],"nodes":[{"children":[1]},{"mesh":0}],)"
               R"("meshes":[{"primitives":[{"attributes":{"POSITION":)" +
               std::to_string(positions) + R"(}}]}],"animations":[{"samplers":[{"input":)" +
               std::to_string(input) + R"(,"output":)" + std::to_string(output) +
               R"(,"interpolation":")" + interpolation + R"("}],"channels":[{)" + channel + "}]}]";
    }
};

// The error for a translation sampler with these keys, or empty when the file loads.
std::string samplerError(const std::string& name, const std::vector<float>& times,
                         const std::vector<float>& values,
                         const std::string& interpolation = "LINEAR") {
    AnimatedTriangle t;
    const int in = t.g.floats(times, "SCALAR");
    const int out = t.g.floats(values, "VEC3");
    return loadError(
        t.g.write(test::tempDir("gltf_anim"), name, t.document(in, out, interpolation)));
}

bool mentions(const std::string& error, const std::string& what) {
    return error.find(what) != std::string::npos && error.find('\n') == std::string::npos;
}

TEST(GltfAnimation, ARigidlyMovedTriangleGoesIntoTheRig) {
    AnimatedTriangle t;
    const int in = t.g.floats({0.0f, 1.0f}, "SCALAR");
    const int out = t.g.floats({0, 0, 0, 0, 2, 0}, "VEC3");
    const Scene s = loadGltf(t.g.write(test::tempDir("gltf_anim"), "ok.gltf", t.document(in, out)));
    ASSERT_TRUE(s.rig);
    EXPECT_EQ(s.triangleCount(), 0u);
    ASSERT_EQ(s.rig->instances.size(), 1u);
    EXPECT_EQ(s.rig->instances[0].skin, -1);
    EXPECT_EQ(s.rig->nodes[s.rig->instances[0].node].parent, 0);
    EXPECT_EQ(s.rig->animations[0].samplers[0].components, 3u);
    EXPECT_FLOAT_EQ(s.rig->animations[0].duration, 1.0f);
    EXPECT_EQ(s.rig->lightNodes.size(), s.lights.size()); // the default sun, which stands still
    EXPECT_EQ(s.rig->lightNodes.at(0), -1);
    // The camera is framed on the triangle where it rests.
    EXPECT_LT(glm::length(s.camera.position), 10.0f);
}

TEST(GltfAnimation, AFileWithoutAnimationHasNoRig) {
    const Scene s = loadGltf(test::writeQuadGltf(test::tempDir("gltf_anim")));
    EXPECT_FALSE(s.rig);
    EXPECT_EQ(s.triangleCount(), 2u);
}

TEST(GltfAnimation, BadSamplerKeysAreOneLineErrors) {
    std::string e = samplerError("order.gltf", {0, 1, 2, 3, 4, 5, 4.5f}, std::vector<float>(21, 0));
    EXPECT_TRUE(
        mentions(e, "order.gltf: animation 0 sampler 0: input times not increasing at key 6"))
        << e;
    e = samplerError("equal.gltf", {0, 1, 1}, std::vector<float>(9, 0));
    EXPECT_TRUE(mentions(e, "animation 0 sampler 0: input times not increasing at key 2")) << e;
    e = samplerError("negative.gltf", {-1, 0}, std::vector<float>(6, 0));
    EXPECT_TRUE(mentions(e, "animation 0 sampler 0: input time -1 is negative at key 0")) << e;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    e = samplerError("nantime.gltf", {0, nan}, std::vector<float>(6, 0));
    EXPECT_TRUE(mentions(e, "input time is not a finite number at key 1")) << e;
    e = samplerError("nanvalue.gltf", {0, 1},
                     {0, 0, 0, 0, std::numeric_limits<float>::infinity(), 0});
    EXPECT_TRUE(
        mentions(e, "animation 0 sampler 0: output value is not a finite number at element 1"))
        << e;
    e = samplerError("count.gltf", {0, 1, 2}, std::vector<float>(6, 0));
    EXPECT_TRUE(mentions(e, "animation 0 sampler 0: output has 2 elements, expected 3")) << e;
    e = samplerError("cubic.gltf", {0, 1, 2}, std::vector<float>(9, 0), "CUBICSPLINE");
    EXPECT_TRUE(mentions(e, "output has 3 elements, expected 9")) << e;
    EXPECT_TRUE(mentions(e, "CUBICSPLINE")) << e;
    EXPECT_EQ(samplerError("cubicok.gltf", {0, 1, 2}, std::vector<float>(27, 0), "CUBICSPLINE"),
              "");
    e = samplerError("interp.gltf", {0, 1}, std::vector<float>(6, 0), "SMOOTH");
    EXPECT_TRUE(mentions(e, "animation 0 sampler 0: interpolation 'SMOOTH'")) << e;
}

TEST(GltfAnimation, ChannelsNamingWhatIsNotThereAreOneLineErrors) {
    const auto dir = test::tempDir("gltf_anim");
    const auto error = [&](const std::string& name, const std::string& channel) {
        AnimatedTriangle t;
        const int in = t.g.floats({0, 1}, "SCALAR");
        const int out = t.g.floats(std::vector<float>(6, 0), "VEC3");
        return loadError(t.g.write(dir, name, t.document(in, out, "LINEAR", channel)));
    };
    std::string e =
        error("sampler.gltf", R"("sampler":3,"target":{"node":0,"path":"translation"})");
    EXPECT_TRUE(mentions(e, "sampler.gltf: ")) << e;
    EXPECT_TRUE(mentions(e, "sampler is 3, but animations[0] has 1 samplers")) << e;
    e = error("node.gltf", R"("sampler":0,"target":{"node":9,"path":"translation"})");
    EXPECT_TRUE(mentions(e, "animations[0].channels[0].target.node")) << e;
    e = error("weights.gltf", R"("sampler":0,"target":{"node":1,"path":"weights"})");
    EXPECT_TRUE(mentions(e, "animation 0 channel 0: sampler 0's output has 3 components")) << e;
    e = error("rotation.gltf", R"("sampler":0,"target":{"node":1,"path":"rotation"})");
    EXPECT_TRUE(mentions(e, "rotation needs 4")) << e;
}

// Node 0 is a skinned bar with joints nodes 1 and 2; mesh 0 has one morph target.
struct SkinnedBar {
    TinyGltf g;
    int positions = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3");

    // With `second`, a second morph target (the mesh's weights then 0.25 and 0.5).
    std::string document(int joints, int weights, int ibm, int target, int second = -1) const {
        const std::string targets =
            R"({"POSITION":)" + std::to_string(target) + "}" +
            (second < 0 ? "" : R"(,{"POSITION":)" + std::to_string(second) + "}");
        return R"("scenes":[{"nodes":[0,1]}],"nodes":[{"mesh":0,"skin":0},{"children":[2]},)"
               R"({"translation":[0,1,0]}],"skins":[{"joints":[1,2],"inverseBindMatrices":)" +
               std::to_string(ibm) + R"(}],"meshes":[{"weights":)" +
               (second < 0 ? "[0.25]" : "[0.25,0.5]") +
               R"(,"primitives":[{"attributes":{"POSITION":)" + std::to_string(positions) +
               R"(,"JOINTS_0":)" + std::to_string(joints) + R"(,"WEIGHTS_0":)" +
               std::to_string(weights) + R"(},"targets":[)" + targets + "]}]}]";
    }
};

std::vector<float> identities(int n) {
    std::vector<float> m;
    for (int i = 0; i < n; ++i) {
        for (int k = 0; k < 16; ++k)
            m.push_back(k % 5 == 0 ? 1.0f : 0.0f);
    }
    return m;
}

TEST(GltfAnimation, SkinsAndMorphTargetsAreRead) {
    SkinnedBar b;
    const int joints = b.g.bytes({0, 1, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0}, "VEC4", false);
    // Normalised unsigned bytes: 128/255 + 127/255 = 1, 255/255, and 51 + 51 that sum to 0.4
    // and are scaled to 1.
    const int weights = b.g.bytes({128, 127, 0, 0, 255, 0, 0, 0, 51, 51, 0, 0}, "VEC4", true);
    const int ibm = b.g.floats(identities(2), "MAT4");
    // A sparse target: only vertex 2 moves, by +1 in z.
    const int target = b.g.sparseFloats(3, "VEC3", {2}, {0, 0, 1});
    const Scene s = loadGltf(b.g.write(test::tempDir("gltf_anim"), "bar.gltf",
                                       b.document(joints, weights, ibm, target)));
    ASSERT_TRUE(s.rig);
    const Rig& rig = *s.rig;
    ASSERT_EQ(rig.instances.size(), 1u);
    EXPECT_EQ(rig.instances[0].skin, 0);
    ASSERT_EQ(rig.skins.size(), 1u);
    // Joints name rig nodes: glTF nodes 1 and 2, parents first.
    const Skin& skin = rig.skins[0];
    ASSERT_EQ(skin.joints.size(), 2u);
    EXPECT_EQ(rig.nodes[skin.joints[1]].parent, static_cast<int>(skin.joints[0]));
    EXPECT_FLOAT_EQ(rig.nodes[skin.joints[1]].rest.translation.y, 1.0f);
    const RigMesh& m = rig.meshes[rig.instances[0].mesh];
    ASSERT_EQ(m.vertices.size(), 3u);
    ASSERT_EQ(m.joints.size(), 3u);
    EXPECT_EQ(m.joints[0], glm::uvec4(0, 1, 0, 0));
    EXPECT_NEAR(m.weights[0].x, 128.0f / 255.0f, 1e-6f);
    EXPECT_NEAR(m.weights[0].y, 127.0f / 255.0f, 1e-6f);
    EXPECT_FLOAT_EQ(m.weights[1].x, 1.0f);
    EXPECT_FLOAT_EQ(m.weights[2].x, 0.5f);
    EXPECT_FLOAT_EQ(m.weights[2].y, 0.5f);
    ASSERT_EQ(m.targets.size(), 1u);
    ASSERT_EQ(m.targets[0].positions.size(), 3u);
    EXPECT_TRUE(m.targets[0].normals.empty());
    EXPECT_EQ(m.targets[0].positions[2], glm::vec3(0, 0, 1));
    EXPECT_EQ(m.targets[0].positions[0], glm::vec3(0));
    // The node's default weights come from its mesh.
    ASSERT_EQ(rig.nodes[rig.instances[0].node].weights.size(), 1u);
    EXPECT_FLOAT_EQ(rig.nodes[rig.instances[0].node].weights[0], 0.25f);
}

TEST(GltfAnimation, BadSkinsAndTargetsAreOneLineErrors) {
    const auto dir = test::tempDir("gltf_anim");
    const std::vector<uint8_t> goodJoints{0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0};
    const auto error = [&](const std::string& name, const std::vector<uint8_t>& joints,
                           int matrices, std::size_t targetCount) {
        SkinnedBar b;
        const int j = b.g.bytes(joints, "VEC4", false);
        const int w = b.g.floats({1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, "VEC4");
        const int ibm = b.g.floats(identities(matrices), "MAT4");
        const int t = b.g.floats(std::vector<float>(3 * targetCount, 0.0f), "VEC3");
        return loadError(b.g.write(dir, name, b.document(j, w, ibm, t)));
    };
    EXPECT_EQ(error("ok.gltf", goodJoints, 2, 3), "");
    std::string e = error("joints.gltf", {0, 1, 0, 0, 1, 0, 0, 0, 0, 2, 0, 0}, 2, 3);
    EXPECT_TRUE(mentions(e, "joints.gltf: mesh '' primitive 0 vertex 2: joint 2 is out of range "
                            "of skin 0's 2 joints"))
        << e;
    e = error("ibm.gltf", goodJoints, 1, 3);
    EXPECT_TRUE(mentions(e, "ibm.gltf: skin 0: inverseBindMatrices has 1 matrices, fewer than its "
                            "2 joints"))
        << e;
    e = error("target.gltf", goodJoints, 2, 2);
    EXPECT_TRUE(mentions(e, "target.gltf: mesh '' primitive 0 morph target 0: POSITION has 2 "
                            "elements, the primitive 3 vertices"))
        << e;
}

TEST(GltfAnimation, WeightsChannelsMatchTheMorphTargetCount) {
    const auto dir = test::tempDir("gltf_anim");
    // Two morph targets: a weights key holds two values.
    const auto write = [&](const std::string& name, std::size_t values) {
        SkinnedBar b;
        const int j = b.g.bytes({0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, "VEC4", false);
        const int w = b.g.floats({1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, "VEC4");
        const int ibm = b.g.floats(identities(2), "MAT4");
        const int t = b.g.floats(std::vector<float>(9, 0.0f), "VEC3");
        const int t2 = b.g.floats(std::vector<float>(9, 1.0f), "VEC3");
        const int in = b.g.floats({0, 1}, "SCALAR");
        const int out = b.g.floats(std::vector<float>(values, 0.5f), "SCALAR");
        return b.g.write(
            dir, name,
            b.document(j, w, ibm, t, t2) + R"(,"animations":[{"samplers":[{"input":)" +
                std::to_string(in) + R"(,"output":)" + std::to_string(out) +
                R"(}],"channels":[{"sampler":0,"target":{"node":0,"path":"weights"}}]}])");
    };
    const Scene s = loadGltf(write("ok.gltf", 4));
    ASSERT_TRUE(s.rig);
    EXPECT_EQ(s.rig->animations.at(0).samplers.at(0).components, 2u);
    const auto& weights = s.rig->nodes[s.rig->instances.at(0).node].weights;
    EXPECT_EQ(weights, (std::vector<float>{0.25f, 0.5f}));
    const std::string e = loadError(write("weights.gltf", 2));
    EXPECT_TRUE(mentions(e,
                         "weights.gltf: animation 0 sampler 0: output has 2 elements, expected 4 "
                         "(2 keys x 2 morph targets)"))
        << e;
}

} // namespace
} // namespace gt::scene
