// OpenSubdiv refinement of subdivision cages and the geometric LOD levels (Guenter et al. 2012,
// section 6).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.hpp"
#include "scene/builtin_scenes.hpp"
#include "scene/bvh.hpp"
#include "scene/gltf_loader.hpp"
#include "scene/subdivision.hpp"
#include "support/gltf_fixtures.hpp"
#include "support/gpu_test_context.hpp"
#include "trace/gpu_scene.hpp"

namespace gt::scene {
namespace {

SubdivisionCage cubeCage() {
    Scene s;
    s.materials.push_back({});
    SceneBuilder(s).boxCage(glm::mat4(1.0f), 0);
    return s.cages.front();
}

TEST(Subdivision, CubeCageFaceCountsPerLevel) {
    // Catmull-Clark turns every quad into four: 6, 24, 96, 384 faces, two triangles each.
    const SubdivisionCage cube = cubeCage();
    std::size_t faces = 6;
    for (uint32_t level = 0; level <= 3; ++level) {
        EXPECT_EQ(refinedFaceCount(cube, level), faces) << level;
        EXPECT_EQ(refineCage(cube, level).size(), std::size_t{6} * faces) << level;
        faces *= 4;
    }
    // A triangle cage: each triangle becomes three quads at the first level.
    SubdivisionCage tetra;
    tetra.points = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    tetra.faceSizes = {3, 3, 3, 3};
    tetra.indices = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    EXPECT_EQ(refinedFaceCount(tetra, 1), 12u);
    EXPECT_EQ(refinedFaceCount(tetra, 2), 48u);
}

TEST(Subdivision, VerticesLieOnOneSmoothSurfaceWithOutwardNormals) {
    // Every level's vertices are on the limit surface, so the levels converge on it: the
    // cube's limit is a rounded blob inside the cage, and its points' distance from the centre
    // stays within the same range at every level.
    const SubdivisionCage cube = cubeCage();
    for (uint32_t level = 1; level <= 3; ++level) {
        float lo = 1e9f, hi = 0.0f;
        for (const Vertex& v : refineCage(cube, level)) {
            const float r = glm::length(v.position);
            lo = std::min(lo, r);
            hi = std::max(hi, r);
            EXPECT_NEAR(glm::length(v.normal), 1.0f, 1e-4f);
            EXPECT_GT(glm::dot(v.normal, v.position), 0.0f); // outward
            for (int a = 0; a < 3; ++a) {
                EXPECT_LE(std::abs(v.position[a]), 0.5f);
            }
        }
        EXPECT_GT(lo, 0.25f) << level;
        EXPECT_LT(hi, 0.5f * std::sqrt(3.0f)) << level;
    }
}

TEST(Subdivision, BadCagesAreErrorsNamingThem) {
    SubdivisionCage c = cubeCage();
    c.name = "broken";
    c.indices[5] = 99;
    try {
        (void)refineCage(c, 1);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("broken"), std::string::npos) << e.what();
    }
    c = cubeCage();
    c.faceSizes[0] = 2;
    EXPECT_THROW((void)refineCage(c, 1), Error);
}

TEST(Subdivision, LodFollowsTheSamplingPitch) {
    EXPECT_EQ(lodForPitch(1.0f, 3), 0u);
    EXPECT_EQ(lodForPitch(3.9f, 3), 0u);  // the middle layer (s ~ 2) keeps full detail
    EXPECT_EQ(lodForPitch(4.73f, 3), 1u); // the outer layer at slope A
    EXPECT_EQ(lodForPitch(8.0f, 3), 2u);
    EXPECT_EQ(lodForPitch(100.0f, 3), 2u);
    EXPECT_EQ(lodForPitch(100.0f, 1), 0u); // a scene without cages
}

TEST(Subdivision, GalleryLevelsHalveTheTriangles) {
    const Scene gallery = makeBuiltin("builtin:gallery");
    ASSERT_FALSE(gallery.cages.empty());
    std::vector<std::size_t> counts(kLodRefinements.size());
    std::transform(kLodRefinements.begin(), kLodRefinements.end(), counts.begin(),
                   [&](uint32_t r) { return refinedGeometry(gallery, r).triangleCount(); });
    const std::size_t room = gallery.triangleCount();
    for (std::size_t l = 1; l < counts.size(); ++l) {
        EXPECT_EQ(4 * (counts[l] - room), counts[l - 1] - room) << l; // cage triangles / 4
    }
}

TEST(Subdivision, PackedLevelsKeepTheirOwnTrees) {
    // Two levels in one set of tables: level 1's root, nodes and leaves point into level 1's
    // part, and its triangles follow level 0's.
    const Scene gallery = makeBuiltin("builtin:gallery");
    const Scene fine = refinedGeometry(gallery, 2), coarse = refinedGeometry(gallery, 1);
    const Bvh fineBvh(fine), coarseBvh(coarse);
    const std::array levels{trace::LodGeometry{&fine, &fineBvh},
                            trace::LodGeometry{&coarse, &coarseBvh}};
    const trace::PackedScene p = trace::packScene(levels);
    const uint32_t root1 = p.uniforms.lodRoots.y;
    EXPECT_EQ(p.uniforms.lodRoots.x, 0u);
    EXPECT_EQ(root1, fineBvh.nodes().size());
    EXPECT_EQ(p.uniforms.lodRoots.z, root1); // levels past the last repeat it
    EXPECT_EQ(p.triangles.size(), 3 * (fine.triangleCount() + coarse.triangleCount()));
    const auto triBase = static_cast<uint32_t>(fine.triangleCount());
    for (std::size_t n = root1; n < p.nodes.size() / 2; ++n) {
        const uint32_t first = std::bit_cast<uint32_t>(p.nodes[2 * n].w);
        const uint32_t count = std::bit_cast<uint32_t>(p.nodes[2 * n + 1].w);
        if (count > 0) {
            EXPECT_GE(first, triBase);
            EXPECT_LE(first + count, triBase + coarse.triangleCount());
        } else {
            EXPECT_GT(first, root1);
            EXPECT_LT(first + 1, p.nodes.size() / 2);
        }
    }
}

// The glTF convention: a mesh with extras.gazetrace_subdivision = "catmull-clark" is a cage; with
// gazetrace_quads, triangle pairs (a, b, c), (a, c, d) are quads. A cube written as 12
// triangles over 8 shared corners.
std::filesystem::path writeCubeGltf(const std::filesystem::path& dir, const std::string& extras) {
    std::vector<float> pos;
    for (int i = 0; i < 8; ++i) {
        pos.insert(pos.end(),
                   {(i & 1) ? 0.5f : -0.5f, (i & 2) ? 0.5f : -0.5f, (i & 4) ? 0.5f : -0.5f});
    }
    const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    std::vector<uint16_t> idx;
    for (const auto& q : quads) {
        for (const uint32_t i : {q[0], q[1], q[2], q[0], q[2], q[3]}) {
            idx.push_back(static_cast<uint16_t>(i));
        }
    }
    std::vector<uint8_t> bin(pos.size() * 4 + idx.size() * 2);
    std::memcpy(bin.data(), pos.data(), pos.size() * 4);
    std::memcpy(bin.data() + pos.size() * 4, idx.data(), idx.size() * 2);
    test::writeFile(dir / "cube.bin", bin.data(), bin.size());
    const std::string json = R"({"asset": {"version": "2.0"}, "scene": 0,
  "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "translation": [0, 1, 0]}],
  "meshes": [{"name": "blob", "extras": )" +
                             extras + R"(,
              "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "buffers": [{"uri": "cube.bin", "byteLength": 168}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 96},
                  {"buffer": 0, "byteOffset": 96, "byteLength": 72}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3",
                 "min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]},
                {"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"}]})";
    test::writeFile(dir / "cube.gltf", json.data(), json.size());
    return dir / "cube.gltf";
}

TEST(Subdivision, GltfMeshesMarkedAsCagesAreRefined) {
    const auto dir = test::tempDir("gltf_cage");
    Scene s = loadGltf(writeCubeGltf(
        dir, R"({"gazetrace_subdivision": "catmull-clark", "gazetrace_quads": true})"));
    ASSERT_EQ(s.cages.size(), 1u);
    EXPECT_EQ(s.triangleCount(), 0u); // the cage's triangles are not drawn as they are
    EXPECT_EQ(s.cages[0].name, "blob");
    EXPECT_EQ(s.cages[0].points.size(), 8u); // welded
    EXPECT_EQ(s.cages[0].faceSizes, std::vector<uint32_t>(6, 4));
    EXPECT_FLOAT_EQ(s.boundsMax().y, 1.5f); // the node's transform applied
    EXPECT_EQ(refinedGeometry(s, 3).triangleCount(), 2u * 6 * 64);
    // Without the quad flag, the twelve triangles are the cage's faces.
    s = loadGltf(writeCubeGltf(dir, R"({"gazetrace_subdivision": "catmull-clark"})"));
    EXPECT_EQ(s.cages[0].faceSizes, std::vector<uint32_t>(12, 3));
    // Without the mark, plain triangles; an unknown scheme is an error naming the mesh.
    s = loadGltf(writeCubeGltf(dir, R"({"author": "x"})"));
    EXPECT_TRUE(s.cages.empty());
    EXPECT_EQ(s.triangleCount(), 12u);
    try {
        (void)loadGltf(writeCubeGltf(dir, R"({"gazetrace_subdivision": "loop"})"));
        FAIL() << "no error";
    } catch (const LoadError& e) {
        EXPECT_NE(std::string(e.what()).find("blob"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace gt::scene
