// The path integrator's sample sequence (shaders/shared/sequence_shared.h, the code the shaders
// compile): shuffled, Owen-scrambled 2-D Sobol' points are a (0, m, 2)-net in every aligned
// block of 2^m indices, for any seed, and different seeds decorrelate.
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "sequence_shared.h"

namespace gt {
namespace {

namespace sq = shaders::sequence;

// Whether 2^m points put exactly one point in each elementary interval
// [i / 2^a, (i + 1) / 2^a) x [j / 2^(m - a), (j + 1) / 2^(m - a)), for every a.
bool isNet(const std::vector<glm::vec2>& points, uint32_t m) {
    const uint32_t n = 1u << m;
    if (points.size() != n) return false;
    for (uint32_t a = 0; a <= m; ++a) {
        std::vector<int> cells(n, 0);
        for (const glm::vec2 p : points) {
            const auto i = static_cast<uint32_t>(p.x * static_cast<float>(1u << a));
            const auto j = static_cast<uint32_t>(p.y * static_cast<float>(1u << (m - a)));
            if (++cells[(i << (m - a)) | j] > 1) return false;
        }
    }
    return true;
}

// Points [first, first + 2^m) with `seed`: a net?
bool isNet(uint32_t first, uint32_t m, uint32_t seed) {
    std::vector<glm::vec2> points;
    for (uint32_t k = 0; k < (1u << m); ++k)
        points.push_back(sq::sobolOwen2(first + k, seed));
    return isNet(points, m);
}

TEST(SampleSequence, EveryAlignedBlockIsANet) {
    for (const uint32_t seed : {0u, 1u, 0xdeadbeefu, sq::sequenceHash(7u)}) {
        for (uint32_t m = 0; m <= 10; ++m) {
            for (const uint32_t block : {0u, 1u, 5u}) {
                EXPECT_TRUE(isNet(block << m, m, seed))
                    << "seed " << seed << ", 2^" << m << " points from " << (block << m);
            }
        }
    }
}

// A pixel pools frames: the rays of frames f and f + 1 at 2 rays per frame are indices 2f and
// 2f + 1, and the 16 of 8 frames are a net as a whole. An unaligned stretch is not a net in
// general, and the test would say so: the first 16 points from index 3 fail for this seed.
TEST(SampleSequence, FramesPoolIntoANet) {
    constexpr uint32_t kRays = 2, kFrames = 8;
    const uint32_t seed = sq::sequenceHash(12345u);
    std::vector<glm::vec2> pooled;
    for (uint32_t f = 0; f < kFrames; ++f) {
        for (uint32_t r = 0; r < kRays; ++r)
            pooled.push_back(sq::sobolOwen2(f * kRays + r, seed));
    }
    EXPECT_TRUE(isNet(pooled, 4));
    EXPECT_FALSE(isNet(3, 4, seed)) << "an unaligned stretch: the check can fail";
}

// Points in [0, 1); each coordinate's mean over a net near 1/2; two seeds give different
// points (the per-pixel, per-decision scramble) that are uncorrelated over a long block.
TEST(SampleSequence, SeedsDecorrelate) {
    constexpr uint32_t kN = 4096;
    double meanX = 0.0, meanY = 0.0, cross = 0.0, meanA = 0.0, meanB = 0.0;
    uint32_t same = 0;
    for (uint32_t k = 0; k < kN; ++k) {
        const glm::vec2 p = sq::sobolOwen2(k, 11u), q = sq::sobolOwen2(k, 12u);
        ASSERT_GE(p.x, 0.0f);
        ASSERT_LT(p.x, 1.0f);
        ASSERT_GE(p.y, 0.0f);
        ASSERT_LT(p.y, 1.0f);
        meanX += p.x / kN;
        meanY += p.y / kN;
        meanA += p.x / kN;
        meanB += q.x / kN;
        cross += static_cast<double>(p.x) * q.x / kN;
        same += p == q ? 1 : 0;
    }
    EXPECT_NEAR(meanX, 0.5, 1e-3);
    EXPECT_NEAR(meanY, 0.5, 1e-3);
    EXPECT_LT(same, 4u);
    // Covariance of uncorrelated uniforms: 0, with a standard error of 1/12 / sqrt(N) = 0.0013.
    EXPECT_NEAR(cross - meanA * meanB, 0.0, 0.006);
}

} // namespace
} // namespace gt
