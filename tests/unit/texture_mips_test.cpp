// Mip chains for ray-cone texture filtering (engine/trace/texture_mips.hpp).
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "scene/bvh.hpp"
#include "trace/gpu_scene.hpp"
#include "trace/texture_mips.hpp"

namespace gt::trace {
namespace {

scene::Texture texture(uint32_t w, uint32_t h, std::vector<uint32_t> rgba) {
    scene::Texture t;
    t.width = w;
    t.height = h;
    t.rgba = std::move(rgba);
    return t;
}

TEST(TextureMips, CountsLevelsDownToOneTexel) {
    EXPECT_EQ(mipLevelCount(1, 1), 1u);
    EXPECT_EQ(mipLevelCount(2, 2), 2u);
    EXPECT_EQ(mipLevelCount(5, 3), 3u);
    EXPECT_EQ(mipLevelCount(1024, 1), 11u);
}

// Black and white average to half the light: sRGB 0.7354, 188 of 255, for a colour texture;
// 128 for data, averaged as stored. Alpha is linear either way.
TEST(TextureMips, AveragesColourInLinearLightAndDataAsStored) {
    const scene::Texture t =
        texture(2, 1, {0x00000000u, 0xffffffffu}); // (0, 0, 0, 0) and (255, 255, 255, 255)
    const std::vector<uint32_t> colour = mipChain(t, true);
    ASSERT_EQ(colour.size(), 1u);
    EXPECT_EQ(colour[0] & 0xffu, 188u);
    EXPECT_EQ((colour[0] >> 16) & 0xffu, 188u);
    EXPECT_EQ(colour[0] >> 24, 128u);
    const std::vector<uint32_t> data = mipChain(t, false);
    ASSERT_EQ(data.size(), 1u);
    EXPECT_EQ(data[0] & 0xffu, 128u);
}

// A 5 x 3 texture halves to 2 x 1, then 1 x 1; the odd column and row fold into the last
// texel, so the red texel at (4, 0) is 1 of its 9.
TEST(TextureMips, HalvesOddSizesDownToOneTexel) {
    std::vector<uint32_t> rgba(15, 0u);
    rgba[4] = 0xffu; // (4, 0): the odd column, red 255
    const std::vector<uint32_t> chain = mipChain(texture(5, 3, rgba), false);
    ASSERT_EQ(chain.size(), 3u);
    EXPECT_EQ(chain[0] & 0xffu, 0u);
    EXPECT_EQ(chain[1] & 0xffu, 28u); // 255 / 9
    EXPECT_EQ(chain[2] & 0xffu, 14u); // 255 / 18
}

// The packed scene holds each texture's level 0 and chain; over a device's texel-buffer limit
// the chains are dropped (level 0 keeps its texels, the info says one level), and past even
// that the upload is refused naming both counts.
TEST(TextureMips, ChainsAreDroppedBeforeTheDevicesTexelLimitIsPassed) {
    scene::Scene s;
    scene::SceneBuilder b(s);
    scene::Material m;
    m.baseColorTexture = 1;
    b.quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, b.material(m));
    s.textures.push_back(texture(4, 4, std::vector<uint32_t>(16, 0x11223344u)));
    s.textures.push_back(texture(2, 2, std::vector<uint32_t>(4, 0xff0000ffu)));
    const scene::Bvh bvh(s);
    const PackedScene p = packScene(s, bvh);
    ASSERT_EQ(p.texels.size(), 16u + 4u + 1u + 4u + 1u); // 4x4, 2x2, 1x1 | 2x2, 1x1
    EXPECT_EQ(p.textureInfo[1], glm::uvec4(21u, 2u, 2u, 2u));
    EXPECT_EQ(fitTextures(p, 26).texels.size(), 26u);
    const FittedTextures level0 = fitTextures(p, 25);
    ASSERT_EQ(level0.texels.size(), 20u);
    EXPECT_EQ(level0.info[1], glm::uvec4(16u, 2u, 2u, 1u));
    EXPECT_EQ(level0.texels[16], 0xff0000ffu);
    try {
        (void)fitTextures(p, 19);
        ADD_FAILURE() << "20 texels fit a limit of 19";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("need 20 texels"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("limit of 19"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace gt::trace
