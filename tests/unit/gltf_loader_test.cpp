// glTF loading: a valid file and every kind of broken one the issue lists.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "scene/builtin_scenes.hpp"
#include "scene/gltf_loader.hpp"
#include "support/gltf_fixtures.hpp"
#include "support/gpu_test_context.hpp"

namespace gt::scene {
namespace {

std::string loadError(const std::filesystem::path& p) {
    try {
        (void)loadGltf(p);
    } catch (const LoadError& e) {
        return e.what();
    }
    return {};
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

TEST(GltfLoader, LoadsEverySharedContentScene) {
    const auto content = test::sharedContent();
    if (content.empty()) GTEST_SKIP() << "../shared/content is absent";
    int loaded = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(content)) {
        const auto ext = entry.path().extension();
        if (ext != ".gltf" && ext != ".glb") continue;
        try {
            const Scene s = loadGltf(entry.path());
            EXPECT_GT(s.triangleCount(), 0u) << entry.path();
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
