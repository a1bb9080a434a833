// glTF loading: a valid file and every kind of broken one the issue lists.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <tuple>
#include <vector>

#include <cstdlib>

#include <gtest/gtest.h>
#include <stb_image_write.h>
#include <sys/stat.h>

#include "core/error.hpp"
#include "scene/animation.hpp"
#include "scene/builtin_scenes.hpp"
#include "scene/gltf_loader.hpp"
#include "support/bad_files.hpp"
#include "support/gltf_fixtures.hpp"
#include "support/gpu_test_context.hpp"

namespace gt::scene {
namespace {

using test::loadError;

// `json` with its first `from` replaced by `to`, written to dir/name; a `from` that is not there
// fails the test (the fixture changed under it).
std::filesystem::path writeEdited(const std::filesystem::path& dir, const std::string& name,
                                  std::string json, const std::string& from,
                                  const std::string& to) {
    const auto at = json.find(from);
    if (at == std::string::npos) {
        ADD_FAILURE() << "'" << from << "' is not in the fixture";
    } else {
        json.replace(at, from.size(), to);
    }
    test::writeFile(dir / name, json.data(), json.size());
    return dir / name;
}

TEST(GltfLoader, LoadsMeshTransformMaterialAndLight) {
    const auto dir = test::tempDir("gltf");
    const Scene s = loadGltf(test::writeQuadGltf(dir));
    ASSERT_EQ(s.triangleCount(), 2u);
    EXPECT_FLOAT_EQ(s.boundsMax().x, 2.0f); // node scale applied
    EXPECT_FLOAT_EQ(s.boundsMin().z, -2.0f);
    EXPECT_FLOAT_EQ(s.materials[s.triangleMaterial[0]].baseColor.g, 0.25f);
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].type, LightType::Point);
    EXPECT_FLOAT_EQ(s.lights[0].position.y, 2.0f);
    EXPECT_FLOAT_EQ(s.lights[0].intensity, 20.0f);
    // Flat normals were generated (no NORMAL attribute): +-Y.
    EXPECT_NEAR(std::abs(s.vertices[0].normal.y), 1.0f, 1e-6f);
}

TEST(GltfLoader, LoadsGlb) {
    const auto dir = test::tempDir("glb");
    const auto glb = test::quadGlb();
    test::writeFile(dir / "quad.glb", glb.data(), glb.size());
    EXPECT_EQ(loadGltf(dir / "quad.glb").triangleCount(), 2u);
}

TEST(GltfLoader, MissingFileNamesTheFile) {
    const std::string e = loadError("/nonexistent/scene.gltf");
    EXPECT_NE(e.find("/nonexistent/scene.gltf"), std::string::npos) << e;
    EXPECT_NE(e.find("no such file"), std::string::npos) << e;
}

TEST(GltfLoader, TruncatedGlbIsAnError) {
    const auto dir = test::tempDir("trunc");
    auto glb = test::quadGlb();
    for (std::size_t keep : {glb.size() - 20, glb.size() / 2, std::size_t{10}}) {
        test::writeFile(dir / "t.glb", glb.data(), keep);
        const std::string e = loadError(dir / "t.glb");
        EXPECT_FALSE(e.empty()) << "truncated to " << keep << " bytes was accepted";
        EXPECT_NE(e.find("t.glb"), std::string::npos) << e;
        EXPECT_EQ(e.find('\n'), std::string::npos) << "error is not one line: " << e;
    }
}

TEST(GltfLoader, GltfWhoseBufferIsMissing) {
    const auto dir = test::tempDir("nobuf");
    const auto gltf = test::writeQuadGltf(dir);
    std::filesystem::remove(dir / "quad.bin");
    const std::string e = loadError(gltf);
    EXPECT_FALSE(e.empty());
    EXPECT_NE(e.find("quad.gltf"), std::string::npos) << e;
}

TEST(GltfLoader, ShortBufferIsCaughtByAccessorChecks) {
    const auto dir = test::tempDir("short");
    const auto gltf = test::writeQuadGltf(dir);
    const auto bin = test::quadBin();
    test::writeFile(dir / "quad.bin", bin.data(), 30); // shorter than byteLength 60
    EXPECT_FALSE(loadError(gltf).empty());
}

TEST(GltfLoader, GarbageAndWrongExtension) {
    const auto dir = test::tempDir("garbage");
    test::writeFile(dir / "x.gltf", "{ not json", 10);
    EXPECT_NE(loadError(dir / "x.gltf").find("x.gltf"), std::string::npos);
    test::writeFile(dir / "x.obj", "v 0 0 0", 7);
    EXPECT_NE(loadError(dir / "x.obj").find("not a .gltf or .glb"), std::string::npos);
}

TEST(GltfLoader, OutOfRangeIndexIsAnError) {
    const auto dir = test::tempDir("badidx");
    auto bin = test::quadBin();
    const uint16_t bad = 40;
    std::memcpy(bin.data() + 48, &bad, 2);
    test::writeFile(dir / "quad.bin", bin.data(), bin.size());
    const std::string json = test::quadJson("quad.bin");
    test::writeFile(dir / "quad.gltf", json.data(), json.size());
    EXPECT_NE(loadError(dir / "quad.gltf").find("out of range"), std::string::npos);
}

// A quad as gltfpack writes them (KHR_mesh_quantization): SHORT positions scaled by the node,
// BYTE normalised normals, UNSIGNED_BYTE normalised UVs; a sparse accessor moves one corner.
// A second primitive reads TEXCOORD_1, which has no bufferView (zeros) and one sparse value,
// through a KHR_texture_transform, with an unlit material.
std::filesystem::path writeQuantizedQuad(const std::filesystem::path& dir, int sparseIndex) {
    std::vector<uint8_t> bin;
    auto put = [&](const auto& value) {
        const auto* b = reinterpret_cast<const uint8_t*>(&value);
        bin.insert(bin.end(), b, b + sizeof(value));
    };
    const int16_t corners[4][2] = {{-100, -100}, {100, -100}, {100, 100}, {-100, 100}};
    for (const auto& c : corners) { // view 0: positions, stride 8
        put(c[0]), put(int16_t{0}), put(c[1]), put(int16_t{0});
    }
    for (int i = 0; i < 4; ++i) { // view 1 (32): normals, stride 4
        put(int8_t{0}), put(int8_t{90}), put(int8_t{90}), put(int8_t{0});
    }
    const uint8_t uvs[4][2] = {{0, 0}, {255, 0}, {255, 255}, {0, 255}};
    for (const auto& uv : uvs) { // view 2 (48): UVs, stride 4
        put(uv[0]), put(uv[1]), put(uint16_t{0});
    }
    for (uint16_t i : {0, 1, 2, 0, 2, 3}) { // view 3 (64): indices
        put(i);
    }
    put(uint8_t(sparseIndex)), put(uint8_t{0}); // view 4 (76): sparse index, padded to 2
    put(int16_t{100}), put(int16_t{50}), put(int16_t{100}); // view 5 (78): sparse position
    put(uint8_t{1}), put(uint8_t{0});                       // view 6 (84): TEXCOORD_1 index
    put(1.0f), put(1.0f);                                   // view 7 (86): TEXCOORD_1 value
    test::writeFile(dir / "q.bin", bin.data(), bin.size());
    const std::string json = R"({"asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_mesh_quantization", "KHR_texture_transform", "KHR_materials_unlit"],
  "extensionsRequired": ["KHR_mesh_quantization", "KHR_texture_transform"],
  "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0, "scale": [0.01, 0.01, 0.01]}],
  "materials": [{"name": "glass", "alphaMode": "BLEND"},
    {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1, "extensions":
      {"KHR_texture_transform": {"offset": [0.5, 0.25], "scale": [2, 3], "rotation": 1.5707963267948966}}}},
     "alphaMode": "MASK", "alphaCutoff": 0.3, "extensions": {"KHR_materials_unlit": {}}}],
  "textures": [{}],
  "meshes": [{"primitives": [
    {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0},
    {"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_1": 4}, "indices": 3, "material": 1}]}],
  "buffers": [{"uri": "q.bin", "byteLength": )" +
                             std::to_string(bin.size()) + R"(}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 32, "byteStride": 8},
                  {"buffer": 0, "byteOffset": 32, "byteLength": 16, "byteStride": 4},
                  {"buffer": 0, "byteOffset": 48, "byteLength": 16, "byteStride": 4},
                  {"buffer": 0, "byteOffset": 64, "byteLength": 12},
                  {"buffer": 0, "byteOffset": 76, "byteLength": 2},
                  {"buffer": 0, "byteOffset": 78, "byteLength": 6},
                  {"buffer": 0, "byteOffset": 84, "byteLength": 2},
                  {"buffer": 0, "byteOffset": 86, "byteLength": 8}],
  "accessors": [
    {"bufferView": 0, "componentType": 5122, "count": 4, "type": "VEC3",
     "min": [-100, 0, -100], "max": [100, 50, 100],
     "sparse": {"count": 1, "indices": {"bufferView": 4, "componentType": 5121},
                "values": {"bufferView": 5}}},
    {"bufferView": 1, "componentType": 5120, "normalized": true, "count": 4, "type": "VEC3"},
    {"bufferView": 2, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC2"},
    {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"},
    {"componentType": 5126, "count": 4, "type": "VEC2",
     "sparse": {"count": 1, "indices": {"bufferView": 6, "componentType": 5121},
                "values": {"bufferView": 7}}}]})";
    test::writeFile(dir / "q.gltf", json.data(), json.size());
    return dir / "q.gltf";
}

TEST(GltfLoader, QuantizedSparseTransformedAndUnlit) {
    const auto dir = test::tempDir("quantized");
    GltfLoadReport report;
    const Scene s = loadGltf(writeQuantizedQuad(dir, 2), &report);
    ASSERT_EQ(s.triangleCount(), 4u);
    ASSERT_EQ(s.vertices.size(), 12u);
    // SHORT positions, node scale 0.01; the sparse value lifts corner 2 to y = 0.5.
    EXPECT_NEAR(s.vertices[0].position.x, -1.0f, 1e-6f);
    EXPECT_NEAR(s.vertices[1].position.x, 1.0f, 1e-6f);
    EXPECT_NEAR(s.vertices[2].position.y, 0.5f, 1e-6f);
    EXPECT_NEAR(s.vertices[2].position.z, 1.0f, 1e-6f);
    EXPECT_NEAR(s.vertices[0].position.y, 0.0f, 1e-6f);
    // BYTE normalised normals (0, 90, 90) -> (0, 1, 1) / sqrt 2, not the flat face normal.
    EXPECT_NEAR(s.vertices[0].normal.y, std::sqrt(0.5f), 1e-5f);
    EXPECT_NEAR(s.vertices[0].normal.z, std::sqrt(0.5f), 1e-5f);
    // UNSIGNED_BYTE normalised UVs.
    EXPECT_FLOAT_EQ(s.vertices[1].uv.x, 1.0f);
    EXPECT_FLOAT_EQ(s.vertices[2].uv.y, 1.0f);
    // TEXCOORD_1 through the transform: (0, 0) -> offset; (1, 1) -> scale (2, 3), rotated by
    // (cos, sin; -sin, cos) at 90 degrees -> (3, -2), plus offset.
    EXPECT_NEAR(s.vertices[6].uv.x, 0.5f, 1e-6f);
    EXPECT_NEAR(s.vertices[6].uv.y, 0.25f, 1e-6f);
    EXPECT_NEAR(s.vertices[7].uv.x, 3.5f, 1e-5f);
    EXPECT_NEAR(s.vertices[7].uv.y, -1.75f, 1e-5f);
    EXPECT_FALSE(s.materials[s.triangleMaterial[0]].unlit);
    EXPECT_TRUE(s.materials[s.triangleMaterial[2]].unlit);
    // No transparency: a BLEND material is named in a warning, not silently drawn opaque.
    const bool warned = std::any_of(report.warnings.begin(), report.warnings.end(), [](auto& w) {
        return w.find("'glass'") != std::string::npos && w.find("opaque") != std::string::npos;
    });
    EXPECT_TRUE(warned);
    EXPECT_LT(s.materials[s.triangleMaterial[0]].alphaCutoff, 0.0f);
    EXPECT_FLOAT_EQ(s.materials[s.triangleMaterial[2]].alphaCutoff, 0.3f);

    const std::string e = loadError(writeQuantizedQuad(dir, 9));
    EXPECT_NE(e.find("sparse index 9 out of range"), std::string::npos) << e;
    EXPECT_NE(e.find("q.gltf"), std::string::npos) << e;
    // A count no bufferView bounds is refused, not allocated.
    std::ifstream in(writeQuantizedQuad(dir, 2));
    const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string huge = loadError(
        writeEdited(dir, "huge.gltf", json, R"("componentType": 5126, "count": 4, "type": "VEC2")",
                    R"("componentType": 5126, "count": 999999999999, "type": "VEC2")"));
    EXPECT_NE(huge.find("elements, more than 3 x the limit"), std::string::npos) << huge;
}

TEST(GltfLoader, LoadsEverySharedContentScene) {
    const auto content = test::sharedContent();
    if (content.empty()) GTEST_SKIP() << "../shared/content is absent";
    int loaded = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(content)) {
        const auto ext = entry.path().extension();
        if (ext != ".gltf" && ext != ".glb") continue;
        try {
            const Scene s = loadGltf(entry.path());
            // An animated file's moving meshes are in its rig, not among the static triangles.
            const std::size_t moving = s.rig ? s.rig->instances.size() : 0;
            EXPECT_GT(s.triangleCount() + moving, 0u) << entry.path();
            ++loaded;
        } catch (const LoadError& e) {
            ADD_FAILURE() << e.what();
        }
    }
    EXPECT_GT(loaded, 0);
}

TEST(BuiltinScenes, MarketHasTheStudysHardCases) {
    const Scene s = makeMarket();
    EXPECT_GT(s.triangleCount(), 5000u); // many small leaves
    EXPECT_GE(s.lights.size(), 4u);      // ceiling lights
    bool dark = false, bright = false, emissive = false, mirror = false;
    for (const Material& m : s.materials) {
        const float l = (m.baseColor.r + m.baseColor.g + m.baseColor.b) / 3.0f;
        dark |= l < 0.05f;
        bright |= l > 0.8f && m.metallic == 0.0f;
        emissive |= m.emissive.r > 1.0f;
        mirror |= m.metallic >= 1.0f;
    }
    EXPECT_TRUE(dark && bright && emissive && mirror);
    EXPECT_THROW((void)makeBuiltin("builtin:nope"), LoadError);
}

} // namespace
} // namespace gt::scene

namespace gt::scene {
namespace {

// A node translated near the float limit (it crashed the BVH build) is refused with a
// line naming the node; so is one whose scale overflows, and one past the stated limit.
TEST(GltfLoader, RefusesWorldCoordinatesBeyondTheLimitNamingTheNode) {
    const auto dir = test::tempDir("far_node");
    const std::string base = test::quadJsonBesideBin(dir);
    const std::string home = R"({"mesh": 0, "scale": [2, 1, 2]})";
    for (const std::string node : {R"({"mesh": 0, "translation": [3.4e38, 0, 0], "name": "far"})",
                                   R"({"mesh": 0, "translation": [2e38, 0, 0], "name": "far"})",
                                   R"({"mesh": 0, "scale": [1e39, 1, 1], "name": "far"})",
                                   R"({"mesh": 0, "translation": [2e12, 0, 0], "name": "far"})"}) {
        const std::string e = loadError(writeEdited(dir, "far.gltf", base, home, node));
        EXPECT_NE(e.find("node 0 'far'"), std::string::npos) << e;
        EXPECT_NE(e.find("1e12"), std::string::npos) << e;
    }
    const auto near =
        writeEdited(dir, "near.gltf", base, home,
                    R"({"mesh": 0, "translation": [1e9, 0, 0], "scale": [1e8, 1, 1e8]})");
    EXPECT_NO_THROW((void)loadGltf(near)); // inside the limit: fine
}

} // namespace
} // namespace gt::scene

namespace gt::scene {
namespace {

// JSON nested 20,000 deep overflowed the stack inside tinygltf's parser; now it is
// refused before parsing, in .gltf and in .glb. Brackets inside strings do not count.
TEST(GltfLoader, RefusesJsonNestedTooDeep) {
    const auto dir = test::tempDir("deep_json");
    const auto bin = test::quadBin();
    test::writeFile(dir / "quad.bin", bin.data(), bin.size());
    const std::string deep = std::string(20000, '[') + std::string(20000, ']');
    auto withExtras = [](std::string json, const std::string& extras) {
        const std::string asset = R"("asset": {"version": "2.0"})";
        json.replace(json.find(asset), asset.size(),
                     R"("asset": {"version": "2.0", "extras": )" + extras + "}");
        return json;
    };
    const std::string gltf = withExtras(test::quadJson("quad.bin"), deep);
    test::writeFile(dir / "deep.gltf", gltf.data(), gltf.size());
    EXPECT_NE(loadError(dir / "deep.gltf").find("nested more than 256"), std::string::npos);
    const auto glb = test::quadGlb(withExtras(test::quadJson(""), deep));
    test::writeFile(dir / "deep.glb", glb.data(), glb.size());
    EXPECT_NE(loadError(dir / "deep.glb").find("nested more than 256"), std::string::npos);
    // Within the limit, and brackets in a string: loads.
    const std::string fine =
        withExtras(test::quadJson("quad.bin"),
                   std::string(100, '[') + "\"[[[[\\\"[[\"" + std::string(100, ']'));
    test::writeFile(dir / "fine.gltf", fine.data(), fine.size());
    EXPECT_NO_THROW((void)loadGltf(dir / "fine.gltf"));
}

} // namespace
} // namespace gt::scene

namespace gt::scene {
namespace {

// An accessor count of 2^62 said "cannot create std::vector larger than max_size()"
// without the file's name; an empty --scene said ": no such file".
TEST(GltfLoader, HugeCountsAndEmptySpecsNameWhatIsWrong) {
    const auto dir = test::tempDir("huge_count");
    const std::string e = loadError(writeEdited(dir, "huge.gltf", test::quadJsonBesideBin(dir),
                                                R"("count": 4, "type": "VEC3")",
                                                R"("count": 4611686018427387904, "type": "VEC3")"));
    EXPECT_NE(e.find("huge.gltf"), std::string::npos) << e;
    EXPECT_NE(test::thrownMessage<LoadError>([] { (void)loadScene(""); }).find("scene is empty"),
              std::string::npos);
}

} // namespace
} // namespace gt::scene

namespace gt::scene {
namespace {

// 25 nodes, each level referencing the next twice, expand to 2^24 quads (33.6 M
// triangles): it ran out of memory after 135 s. The expansion is counted first and refused with
// the limit; GltfLoadOptions::maxTriangles moves the limit either way.
TEST(GltfLoader, RefusesNodeGraphsThatExpandPastTheTriangleLimit) {
    const auto dir = test::tempDir("dag");
    std::string json = test::quadJsonBesideBin(dir);
    std::string nodes = R"("nodes": [)";
    for (int i = 0; i < 24; ++i) {
        nodes += R"({"children": [)" + std::to_string(i + 1) + "," + std::to_string(i + 1) + "]},";
    }
    nodes += R"({"mesh": 0}])";
    const auto from = json.find(R"("nodes": [{"mesh")"); // the node array, not the scene's list
    ASSERT_NE(from, std::string::npos);
    const auto to = json.find("],\n", from);
    json.replace(from, to + 1 - from, nodes);
    const std::string scenes = R"("scenes": [{"nodes": [0, 1]}])";
    json.replace(json.find(scenes), scenes.size(), R"("scenes": [{"nodes": [0]}])");
    test::writeFile(dir / "dag.gltf", json.data(), json.size());
    std::string e;
    // Refused before any expansion: peak memory, not time, tells (the expansion needs GBs).
    EXPECT_LT(test::peakResidentGrowthKiB([&] { e = loadError(dir / "dag.gltf"); }), 64 * 1024);
    EXPECT_NE(e.find("3.36e+07 triangles"), std::string::npos) << e;
    // The one quad alone is fine, and a lower limit refuses even that.
    const Scene quad = loadGltf(test::writeQuadGltf(dir));
    EXPECT_EQ(quad.triangleCount(), 2u);
    const std::string one = test::thrownMessage<LoadError>(
        [&] { (void)loadGltf(test::writeQuadGltf(dir), nullptr, {.maxTriangles = 1}); });
    EXPECT_NE(one.find("limit of 1"), std::string::npos) << one;
    // Found by fuzzing: the same graph over a mesh without primitives has no triangle to count
    // but 2^25 node instances to visit (11 s a file under ASan). Instances have a limit too.
    const std::string e2 =
        loadError(writeEdited(dir, "empty_dag.gltf", json, R"("primitives")", R"("unknown")"));
    EXPECT_NE(e2.find("3.36e+07 node instances, above the limit of 1e+06"), std::string::npos)
        << e2;
    const std::string few = test::thrownMessage<LoadError>(
        [&] { (void)loadGltf(test::writeQuadGltf(dir), nullptr, {.maxInstances = 0.5}); });
    EXPECT_NE(few.find("node instances, above the limit of 0.5"), std::string::npos) << few;
}

} // namespace
} // namespace gt::scene

namespace gt::scene {
namespace {

// An image `uri` of ../../../../etc/shadow was read. URIs resolve under the model's
// folder: an image outside it is refused with a warning (the material keeps its factor), a
// buffer outside it is an error; GltfLoadOptions::anyPath allows both.
TEST(GltfLoader, UrisStayInsideTheModelsFolder) {
    const auto root = test::tempDir("uri_guard");
    const auto dir = root / "model";
    std::filesystem::create_directories(dir);
    const auto bin = test::quadBin();
    test::writeFile(root / "outside.bin", bin.data(), bin.size());
    test::writeFile(dir / "quad.bin", bin.data(), bin.size());
    std::string json = test::quadJson("quad.bin");
    const std::string material = R"({"pbrMetallicRoughness": {"baseColorFactor")";
    json.replace(
        json.find(material), material.size(),
        R"({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "baseColorFactor")");
    json.insert(json.rfind('}'), R"(, "images": [{"uri": "../../../../etc/hostname"}],
        "textures": [{"source": 0}])");
    test::writeFile(dir / "image.gltf", json.data(), json.size());
    GltfLoadReport report;
    const Scene s = loadGltf(dir / "image.gltf", &report);
    EXPECT_TRUE(s.textures.empty() || s.materials.front().baseColorTexture < 0);
    bool refused = false;
    for (const std::string& w : report.warnings) {
        refused |= w.find("outside the model's folder") != std::string::npos;
    }
    EXPECT_TRUE(refused);
    std::string buf = test::quadJson("../outside.bin");
    test::writeFile(dir / "buffer.gltf", buf.data(), buf.size());
    EXPECT_NE(loadError(dir / "buffer.gltf").find("outside the model's folder"), std::string::npos);
    EXPECT_NO_THROW((void)loadGltf(dir / "buffer.gltf", nullptr, {.anyPath = true}));
}

} // namespace
} // namespace gt::scene

namespace gt::scene {
namespace {

// Found by fuzzing: a light colour of 1.7e117 loaded as an infinite float. Factors outside what
// a float and a sane scene hold are refused, naming the light or material.
TEST(GltfLoader, FactorsBeyondAFloatAreRefused) {
    const auto dir = test::tempDir("factors");
    const std::string base = test::quadJsonBesideBin(dir);
    const std::string light = R"("intensity": 20)";
    const std::string factor = R"("baseColorFactor": [0.5, 0.25, 1.0, 1.0])";
    for (const auto& [from, to, mention] :
         {std::tuple{light, R"("intensity": 20, "color": [1.7e117, 1, 1])",
                     "light 0 color is 1.7e+117"},
          std::tuple{light, R"("intensity": -1)", "light 0 intensity is -1"},
          // Found by fuzzing (UBSan): tinygltf cast 1.5e44 to int.
          std::tuple{std::string(R"({"light": 0})"), R"({"light": 1.5e44})",
                     "KHR_lights_punctual.light is 1.5e+44, must be an integer"},
          std::tuple{factor, R"("baseColorFactor": [0.5, 1e40, 1.0, 1.0])",
                     "baseColorFactor is 1e+40"}}) {
        const std::string e = loadError(writeEdited(dir, "f.gltf", base, from, to));
        EXPECT_NE(e.find(mention), std::string::npos) << e;
    }
}

// A POSITION accessor without a bufferView and a count of 178,956,969 took 122 s and
// 4.3 GB before an error; the first fix (a 2 GiB cap on such accessors) still let it take
// 4.2 GB, which the fuzz replay showed. Now three vertices per triangle of the limit is the
// most an accessor of zeros may hold; peak memory tells whether it was allocated.
TEST(GltfLoader, AnAccessorOfZerosIsBoundedByTheTriangleLimit) {
    const auto dir = test::tempDir("zeros");
    const auto file = writeEdited(dir, "zeros.gltf", test::quadJsonBesideBin(dir),
                                  R"({"bufferView": 0, "componentType": 5126, "count": 4,)",
                                  R"({"componentType": 5126, "count": 178956969,)");
    std::string e;
    EXPECT_LT(test::peakResidentGrowthKiB([&] { e = loadError(file); }), 256 * 1024);
    EXPECT_NE(e.find("178956969 elements, more than 3 x the limit of 2e+07 triangles"),
              std::string::npos)
        << e;
}

} // namespace
} // namespace gt::scene

namespace gt::scene {
namespace {

// Loads `file`, which must be refused with one line naming it and saying `mention`.
void expectRefused(const std::filesystem::path& file, const std::string& mention,
                   const GltfLoadOptions& options = {}) {
    std::string e;
    try {
        (void)loadGltf(file, nullptr, options);
    } catch (const LoadError& x) {
        e = x.what();
    }
    EXPECT_NE(e.find(file.string() + ": "), std::string::npos) << file << " gave '" << e << "'";
    EXPECT_NE(e.find(mention), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

// Sizes and offsets from the file wrapped around in 64-bit arithmetic, so the bounds checks
// passed: a count of (2^64 + 2) / 3 made readFloats allocate 2 floats and write past them
// (SIGSEGV), a bufferView at byteOffset 2^64 - 4 read 4 bytes before its buffer (and loaded).
TEST(GltfLoader, SizesThatWrapAroundAreRefused) {
    const auto dir = test::tempDir("wrap");
    const std::string base = test::quadJsonBesideBin(dir);
    const std::string position = R"("count": 4, "type": "VEC3")";
    for (const auto& [name, from, to, mention] :
         {std::tuple{"count_x3_is_2.gltf", position,
                     R"("count": 6148914691236517206, "type": "VEC3")",
                     "accessors[0] (byteOffset 0, count 6148914691236517206, stride 12) runs "
                     "past the end of bufferViews[0] (48 bytes)"},
          std::tuple{"index_count_2pow63.gltf", std::string(R"("count": 6, "type": "SCALAR")"),
                     R"("count": 9223372036854775809, "type": "SCALAR")",
                     "accessors[1] (byteOffset 0, count 9223372036854775809, stride 2) runs "
                     "past the end"},
          std::tuple{"view_offset_wraps.gltf",
                     std::string(R"({"buffer": 0, "byteOffset": 0, "byteLength": 48})"),
                     R"({"buffer": 0, "byteOffset": 18446744073709551612, "byteLength": 52})",
                     "bufferViews[0] (byteOffset 18446744073709551612, byteLength 52) runs "
                     "past the end of buffers[0] (60 bytes)"},
          std::tuple{
              "accessor_offset_wraps.gltf",
              std::string(R"({"bufferView": 0, "componentType": 5126,)"),
              R"({"bufferView": 0, "byteOffset": 18446744073709551612, "componentType": 5126,)",
              "accessors[0] (byteOffset 18446744073709551612, count 4, stride 12) runs "
              "past the end"},
          std::tuple{"sparse_count_wraps.gltf", position,
                     R"("count": 4, "type": "VEC3", "sparse": {"count": 4,
                           "indices": {"bufferView": 1, "componentType": 5125,
                                       "byteOffset": 18446744073709551612},
                           "values": {"bufferView": 0}})",
                     "accessors[0].sparse.indices (byteOffset 18446744073709551612, 4 x 4 "
                     "bytes) runs past the end of bufferViews[1] (12 bytes)"},
          // tinygltf hands an image's bufferView to the decoder unchecked.
          std::tuple{"image_view_wraps.gltf",
                     std::string(R"({"buffer": 0, "byteOffset": 48, "byteLength": 12}])"),
                     R"({"buffer": 0, "byteOffset": 48, "byteLength": 12},
                           {"buffer": 0, "byteOffset": 18446744073709551612, "byteLength": 8}],
                           "images": [{"bufferView": 2, "mimeType": "image/png"}])",
                     "bufferViews[2] (byteOffset 18446744073709551612, byteLength 8) runs past "
                     "the end of buffers[0]"}}) {
        expectRefused(writeEdited(dir, name, base, from, to), mention);
    }
}

// What the glTF 2.0 specification says a file MUST do, which tinygltf alone lets through: it
// reads a negative byteOffset or byteStride as 0, casts a 64-bit index to int (4294967297 names
// accessor 1), and ignores a 15-number matrix; nor does it check that a morph target names an
// existing accessor or that a spot light's inner cone is narrower than its outer one.
TEST(GltfLoader, WhatTheSpecificationForbidsIsRefusedNamingTheField) {
    const auto dir = test::tempDir("must");
    const std::string base = test::quadJsonBesideBin(dir);
    const std::string view0 = R"({"buffer": 0, "byteOffset": 0, "byteLength": 48})";
    const std::string prim = R"("indices": 1, "material": 0)";
    const std::string node = R"({"mesh": 0, "scale": [2, 1, 2]})";
    const std::string light = R"({"type": "point", "intensity": 20})";
    for (const auto& [from, to, mention] :
         {std::tuple{std::string(R"({"bufferView": 0, "componentType": 5126,)"),
                     std::string(R"({"bufferView": 0, "byteOffset": -4, "componentType": 5126,)"),
                     "accessors[0].byteOffset is -4, must be >= 0"},
          std::tuple{view0, std::string(R"({"buffer": 0, "byteOffset": -8, "byteLength": 48})"),
                     "bufferViews[0].byteOffset is -8, must be >= 0"},
          std::tuple{view0, std::string(R"({"buffer": 0, "byteLength": 48, "byteStride": -12})"),
                     "bufferViews[0].byteStride is -12, must be >= 4"},
          std::tuple{view0, std::string(R"({"buffer": 0, "byteLength": 48, "byteStride": 14})"),
                     "bufferViews[0].byteStride is 14, must be a multiple of 4"},
          std::tuple{view0, std::string(R"({"buffer": 0, "byteLength": 48, "byteStride": 256})"),
                     "bufferViews[0].byteStride is 256, must be <= 252"},
          std::tuple{view0, std::string(R"({"buffer": 0, "byteLength": 48.5})"),
                     "bufferViews[0].byteLength is 48.5, must be an integer"},
          std::tuple{prim, std::string(R"("indices": 4294967297, "material": 0)"),
                     "meshes[0].primitives[0].indices is 4294967297, but there are 2 entries "
                     "in accessors"},
          std::tuple{node, std::string(R"({"mesh": 4294967296})"),
                     "nodes[0].mesh is 4294967296, but there is 1 entry in meshes"},
          std::tuple{node,
                     std::string(R"({"mesh": 0, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 5,0,0]})"),
                     "nodes[0].matrix has 15 numbers, must have 16"},
          std::tuple{prim,
                     std::string(R"("indices": 1, "material": 0, "targets": [{"POSITION": 9}])"),
                     "meshes[0].primitives[0].targets[0].POSITION is 9, but there are 2 "
                     "entries in accessors"},
          std::tuple{
              light,
              std::string(
                  R"({"type": "spot", "spot": {"innerConeAngle": 0.7, "outerConeAngle": 0.3}})"),
              "extensions.KHR_lights_punctual.lights[0].spot innerConeAngle 0.7 and "
              "outerConeAngle 0.3: must be 0 <= inner < outer <= pi/2"},
          std::tuple{light, std::string(R"({"type": "spot", "spot": {"outerConeAngle": 2}})"),
                     "must be 0 <= inner < outer <= pi/2"},
          std::tuple{std::string(R"("count": 6, "type": "SCALAR")"),
                     std::string(R"("count": 0, "type": "SCALAR")"),
                     "accessors[1].count is 0, must be >= 1"},
          // "quad.bin%00.png" read quad.bin.
          std::tuple{std::string(R"("uri": "quad.bin")"),
                     std::string(R"("uri": "quad.bin%00.png")"),
                     "buffers[0].uri holds %00 (a NUL), which no file name can"},
          // A "3.0" asset loaded as 2.0.
          std::tuple{std::string(R"("version": "2.0")"), std::string(R"("version": "3.0")"),
                     "asset.version is \"3.0\", must be 2.x"},
          std::tuple{std::string(R"("version": "2.0")"), std::string(R"("version": 2)"),
                     "asset.version is 2, must be 2.x"}}) {
        expectRefused(writeEdited(dir, "must.gltf", base, from, to), mention);
    }
}

std::vector<uint8_t> withHeaderWord(std::vector<uint8_t> glb, std::size_t offset, uint32_t v) {
    std::memcpy(glb.data() + offset, &v, 4);
    return glb;
}

// A GLB of version 1 or 99 loaded as version 2; chunk lengths near 2^32 are refused by a
// check that cannot wrap; the JSON (chunk or file) is UTF-8 without a byte-order mark or NUL.
TEST(GltfLoader, GlbHeaderAndJsonTextAreChecked) {
    const auto dir = test::tempDir("glb_header");
    const auto glb = test::quadGlb();
    const auto write = [&](const std::string& name, const std::vector<uint8_t>& bytes) {
        test::writeFile(dir / name, bytes.data(), bytes.size());
        return dir / name;
    };
    expectRefused(write("v1.glb", withHeaderWord(glb, 4, 1)), "GLB header version is 1, must be 2");
    expectRefused(write("v99.glb", withHeaderWord(glb, 4, 99)), "GLB header version is 99");
    expectRefused(write("json_huge.glb", withHeaderWord(glb, 12, 0xFFFFFFFCu)),
                  "GLB chunk 0 length 4294967292 at byte 12 runs past the GLB length");
    uint32_t jsonLength = 0;
    std::memcpy(&jsonLength, glb.data() + 12, 4);
    const std::size_t binHeader = 20 + std::size_t{jsonLength};
    expectRefused(write("bin_huge.glb", withHeaderWord(glb, binHeader, 0xFFFFFFF0u)),
                  "GLB chunk 1 length 4294967280");
    expectRefused(write("long.glb", withHeaderWord(glb, 8, 0xFFFFFFFFu)),
                  "GLB header length is 4294967295 bytes, but the file has");
    auto nul = glb;
    nul[40] = 0;
    expectRefused(write("nul.glb", nul), "the JSON holds a NUL byte at offset 20");
    const std::string json = test::quadJsonBesideBin(dir);
    const std::string bom = "\xEF\xBB\xBF" + json;
    test::writeFile(dir / "bom.gltf", bom.data(), bom.size());
    expectRefused(dir / "bom.gltf", "byte-order mark");
    const std::string latin1 = json.substr(0, 10) + "\xE9" + json.substr(10);
    test::writeFile(dir / "latin1.gltf", latin1.data(), latin1.size());
    expectRefused(dir / "latin1.gltf", "not UTF-8 (byte offset 10)");
    std::string withNul = json;
    withNul.push_back('\0');
    test::writeFile(dir / "nul.gltf", withNul.data(), withNul.size());
    expectRefused(dir / "nul.gltf", "NUL byte");
    EXPECT_EQ(loadGltf(write("fine.glb", glb)).triangleCount(), 2u);
}

// A buffer `uri` naming a folder said only "std::bad_alloc"; one naming a FIFO blocked forever
// (tinygltf opened it to see whether it exists). Both are refused naming the file.
TEST(GltfLoader, BuffersThatAreNotRegularFilesAreRefused) {
    const auto dir = test::tempDir("buffer_kind");
    std::filesystem::create_directories(dir / "folder.bin");
    const std::string folder = test::quadJson("folder.bin");
    test::writeFile(dir / "folder.gltf", folder.data(), folder.size());
    expectRefused(dir / "folder.gltf", "folder.bin: a folder, not a regular file");
    std::filesystem::remove(dir / "fifo.bin");
    ASSERT_EQ(::mkfifo((dir / "fifo.bin").c_str(), 0600), 0);
    const std::string fifo = test::quadJson("fifo.bin");
    test::writeFile(dir / "fifo.gltf", fifo.data(), fifo.size());
    expectRefused(dir / "fifo.gltf", "fifo.bin: a FIFO, not a regular file");
}

// A size x size PNG of one grey, encoded.
std::vector<uint8_t> solidPng(int size, uint8_t value) {
    std::vector<uint8_t> rgba(static_cast<std::size_t>(size) * size * 4, value), png;
    stbi_write_png_to_func(
        [](void* ctx, void* data, int n) {
            auto* out = static_cast<std::vector<uint8_t>*>(ctx);
            out->insert(out->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + n);
        },
        &png, size, size, 4, rgba.data(), size * 4);
    return png;
}

// 400 textures of 2048 x 2048 decoded to 7.5 GB. The sampled textures' decoded size is
// added up from their headers before each is decoded and refused past
// GltfLoadOptions::maxTextureBytes; images no tracer samples (occlusion) are not decoded.
TEST(GltfLoader, DecodedTexturesHaveABudget) {
    const auto dir = test::tempDir("texture_budget");
    std::string json = test::quadJsonBesideBin(dir);
    const std::vector<uint8_t> png = solidPng(64, 200);
    for (int i = 0; i < 3; ++i) {
        test::writeFile(dir / ("t" + std::to_string(i) + ".png"), png.data(), png.size());
    }
    test::writeFile(dir / "broken.png", png.data(), 40); // occlusion only: never decoded
    const std::string materials = R"("materials": [)";
    json.replace(json.find(materials), materials.size(),
                 R"("materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
                   {"pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}},
                   {"pbrMetallicRoughness": {"baseColorTexture": {"index": 2}}},
                   {"occlusionTexture": {"index": 3}},)");
    json.insert(json.rfind('}'), R"(, "images": [{"uri": "t0.png"}, {"uri": "t1.png"},
        {"uri": "t2.png"}, {"uri": "broken.png"}],
        "textures": [{"source": 0}, {"source": 1}, {"source": 2}, {"source": 3}])");
    test::writeFile(dir / "tex.gltf", json.data(), json.size());
    GltfLoadReport report;
    const Scene s = loadGltf(dir / "tex.gltf", &report);
    EXPECT_EQ(s.textures.size(), 3u);
    EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
    // 3 x 16 KiB decoded: two fit in 40 KiB, the third does not.
    expectRefused(dir / "tex.gltf",
                  "decoded textures reach 49152 bytes at image 2 (64x64), over the limit of "
                  "40960 bytes (40 KiB;",
                  {.maxTextureBytes = 40 * 1024});
}

// The path integrator's textures and KHR_materials_transmission / _ior reach the material:
// every sampled texture is decoded (each image a different grey, to tell them apart), the
// normal texture's scale, the transmission factor and the IOR are kept; an IOR below 1 is
// refused naming the field.
TEST(GltfLoader, LoadsNormalEmissiveAndTransmissionTexturesAndTheIor) {
    const auto dir = test::tempDir("gltf_materials");
    std::string json = test::quadJsonBesideBin(dir);
    for (int i = 0; i < 5; ++i) {
        const std::vector<uint8_t> png = solidPng(2, static_cast<uint8_t>(40 * (i + 1)));
        test::writeFile(dir / ("m" + std::to_string(i) + ".png"), png.data(), png.size());
    }
    const std::string materials = R"("materials": [)";
    json.replace(json.find(materials), materials.size(),
                 R"("materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                   "metallicRoughnessTexture": {"index": 3}},
                   "normalTexture": {"index": 1, "scale": 0.5}, "emissiveTexture": {"index": 2},
                   "emissiveFactor": [1, 1, 1],
                   "extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.75,
                   "transmissionTexture": {"index": 4}}, "KHR_materials_ior": {"ior": 1.33}}},)");
    json.insert(json.rfind('}'), R"(, "images": [{"uri": "m0.png"}, {"uri": "m1.png"},
        {"uri": "m2.png"}, {"uri": "m3.png"}, {"uri": "m4.png"}],
        "textures": [{"source": 0}, {"source": 1}, {"source": 2}, {"source": 3}, {"source": 4}])");
    test::writeFile(dir / "m.gltf", json.data(), json.size());
    const Scene s = loadGltf(dir / "m.gltf");
    ASSERT_EQ(s.textures.size(), 5u);
    const Material& m = s.materials.front();
    const auto grey = [&](int t) {
        return t < 0 ? -1 : static_cast<int>(s.textures[t].rgba[0] & 0xffu);
    };
    EXPECT_EQ(grey(m.baseColorTexture), 40);
    EXPECT_EQ(grey(m.normalTexture), 80);
    EXPECT_EQ(grey(m.emissiveTexture), 120);
    EXPECT_EQ(grey(m.metallicRoughnessTexture), 160);
    EXPECT_EQ(grey(m.transmissionTexture), 200);
    EXPECT_FLOAT_EQ(m.normalScale, 0.5f);
    EXPECT_FLOAT_EQ(m.transmission, 0.75f);
    EXPECT_FLOAT_EQ(m.ior, 1.33f);
    const auto bad = writeEdited(dir, "bad.gltf", json, R"("ior": 1.33)", R"("ior": 0.5)");
    EXPECT_NE(test::loadError(bad).find("ior"), std::string::npos) << test::loadError(bad);
}

// A camera on a node scaled by 0 (or by a singular matrix, or 1e30) had NaN or zero axes: the
// render wrote a flat image and exited 0. Such a camera is refused naming its node; a large
// but invertible scale keeps its direction.
TEST(GltfLoader, ACameraWithoutAViewDirectionIsRefused) {
    const auto dir = test::tempDir("camera_axes");
    const std::string base = test::quadJsonBesideBin(dir);
    const std::string light = R"({"translation": [0, 2, 0], "extensions")";
    const auto withCamera = [&](const std::string& transform) {
        std::string json = base;
        json.replace(json.find(light), light.size(),
                     R"({"camera": 0, )" + transform + R"(, "extensions")");
        json.insert(json.rfind('}'), R"(, "cameras": [{"type": "perspective",
            "perspective": {"yfov": 1.0, "znear": 0.1}}])");
        return json;
    };
    for (const std::string& transform :
         {std::string(R"("scale": [0, 0, 0])"), std::string(R"("scale": [1, 0, 1])"),
          std::string(R"("matrix": [0,0,0,0, 0,0,0,0, 0,0,0,0, 0,2,0,1])")}) {
        test::writeFile(dir / "cam.gltf", withCamera(transform).data(),
                        withCamera(transform).size());
        expectRefused(dir / "cam.gltf", "nodes[1] holds the camera, but its world transform "
                                        "leaves the camera no view direction");
    }
    const std::string huge = withCamera(R"("translation": [0, 2, 0], "scale": [1e30, 1e30, 1e30])");
    test::writeFile(dir / "huge.gltf", huge.data(), huge.size());
    const Scene s = loadGltf(dir / "huge.gltf");
    EXPECT_NEAR(s.camera.forward.z, -1.0f, 1e-6f);
    EXPECT_NEAR(s.camera.up.y, 1.0f, 1e-6f);
}

// tinygltf and the JSON parser quote what they failed on: a buffer's data: URI with a bad
// base64 character made an error line as long as the URI (a 200 MB line for a 200 MB file), an
// unterminated string or a 5000-digit number one as long as those. The line keeps the start of
// such a run and its length.
TEST(GltfLoader, ErrorLinesStayShortWhateverTheyQuote) {
    const auto dir = test::tempDir("long_quote");
    const std::string base = test::quadJsonBesideBin(dir);
    const std::string longRun(1 << 20, 'A');
    for (const auto& [name, from, to, mention] :
         {std::tuple{"data_uri.gltf", std::string(R"("uri": "quad.bin")"),
                     R"("uri": "data:application/octet-stream;base64,@@@@)" + longRun + "\"",
                     std::string("...(1048617 characters) in Buffer")},
          std::tuple{"number.gltf", std::string(R"("count": 4,)"),
                     R"("count": 9)" + std::string(5000, '9') + ",",
                     std::string("number overflow parsing '999")},
          std::tuple{"string.gltf", std::string(R"("uri": "quad.bin")"),
                     R"("uri": "quad.bin)" + longRun, std::string("characters)")}}) {
        const auto file = writeEdited(dir, name, base, from, to);
        std::string e;
        try {
            (void)loadGltf(file);
        } catch (const LoadError& x) {
            e = x.what();
        }
        EXPECT_NE(e.find(file.string() + ": "), std::string::npos) << e.substr(0, 300);
        EXPECT_NE(e.find(mention), std::string::npos) << e.substr(0, 300);
        EXPECT_LT(e.size(), 600u) << e.substr(0, 300);
    }
}

} // namespace
} // namespace gt::scene
