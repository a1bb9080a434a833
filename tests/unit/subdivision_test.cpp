// OpenSubdiv refinement of subdivision cages and the geometric LOD levels (seed 002, section 6).
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.hpp"
#include "scene/builtin_scenes.hpp"
#include "scene/bvh.hpp"
#include "scene/subdivision.hpp"
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
        EXPECT_EQ(refineCage(cube, level).size(), 3 * 2 * faces) << level;
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
            for (int a = 0; a < 3; ++a) EXPECT_LE(std::abs(v.position[a]), 0.5f);
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
    EXPECT_EQ(lodForPitch(3.9f, 3), 0u); // the middle layer (s ~ 2) keeps full detail
    EXPECT_EQ(lodForPitch(4.73f, 3), 1u); // the outer layer at slope A
    EXPECT_EQ(lodForPitch(8.0f, 3), 2u);
    EXPECT_EQ(lodForPitch(100.0f, 3), 2u);
    EXPECT_EQ(lodForPitch(100.0f, 1), 0u); // a scene without cages
}

TEST(Subdivision, GalleryLevelsHalveTheTriangles) {
    const Scene gallery = makeBuiltin("builtin:gallery");
    ASSERT_FALSE(gallery.cages.empty());
    std::vector<std::size_t> counts;
    for (const uint32_t r : kLodRefinements) counts.push_back(refinedScene(gallery, r).triangleCount());
    const std::size_t room = gallery.triangleCount();
    for (std::size_t l = 1; l < counts.size(); ++l) {
        EXPECT_EQ(4 * (counts[l] - room), counts[l - 1] - room) << l; // cage triangles / 4
    }
}

TEST(Subdivision, PackedLevelsKeepTheirOwnTrees) {
    // Two levels in one set of tables: level 1's root, nodes and leaves point into level 1's
    // part, and its triangles follow level 0's.
    const Scene gallery = makeBuiltin("builtin:gallery");
    const Scene fine = refinedScene(gallery, 2), coarse = refinedScene(gallery, 1);
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

} // namespace
} // namespace gt::scene
