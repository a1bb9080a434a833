// The point set's chunks (engine/foveation/point_chunks.hpp): point_sample dispatches only those
// kept for a gaze, so every point that lands on screen must be in one, and the chunks must be
// compact enough on the Morton-ordered set to skip most of the canvas with the gaze in a corner.
#include <gtest/gtest.h>

#include "foveation/point_chunks.hpp"
#include "foveation/point_set.hpp"
#include "foveation/sample_canvas.hpp"

namespace gt {
namespace {

using foveation::PointChunks;

foveation::PointSet smallSet() {
    foveation::PointSetParams p;
    p.display = {"small", 160, 144, 0.85};
    return foveation::PointSet::generate(p);
}

// Whether point i, moved by `move` canvas pixels, lands on the W x H screen plus the margin.
bool lands(const foveation::Point& q, glm::vec2 offset, glm::vec2 move, glm::vec2 size) {
    const glm::vec2 s = glm::vec2(q.x, q.y) + offset + move;
    const float m = foveation::kSampleMargin;
    return s.x >= -m && s.y >= -m && s.x < size.x + m && s.y < size.y + m;
}

TEST(PointChunks, EveryPointThatLandsOnScreenIsInAKeptChunk) {
    const foveation::PointSet set = smallSet();
    const PointChunks chunks(set);
    ASSERT_EQ(chunks.count(),
              (set.points().size() + PointChunks::kPoints - 1) / PointChunks::kPoints);
    const glm::vec2 size(160.0f, 144.0f);
    for (const glm::vec2 gaze : {glm::vec2(80.0f, 72.0f), glm::vec2(0.0f, 0.0f),
                                 glm::vec2(160.0f, 20.0f), glm::vec2(-30.0f, 200.0f)}) {
        const glm::vec2 off = foveation::gazeOffset(gaze, 160, 144);
        for (const float siteMove : {0.0f, 1.9f}) {
            const std::vector<uint32_t> kept =
                chunks.onScreen(off, 160, 144, foveation::kSampleMargin, siteMove);
            std::vector<bool> isKept(chunks.count(), false);
            for (const uint32_t c : kept) {
                isKept[c] = true;
            }
            std::size_t missed = 0;
            for (std::size_t i = 0; i < set.points().size(); ++i) {
                const foveation::Point& q = set.points()[i];
                // The farthest the site may move, along each axis and diagonal.
                const float r = siteMove * q.spacing, d = 0.7071f * r;
                bool any = false;
                for (const glm::vec2 m : {glm::vec2(0.0f), glm::vec2(r, 0.0f), glm::vec2(-r, 0.0f),
                                          glm::vec2(0.0f, r), glm::vec2(0.0f, -r), glm::vec2(d, d),
                                          glm::vec2(-d, d), glm::vec2(d, -d), glm::vec2(-d, -d)}) {
                    any = any || lands(q, off, m, size);
                }
                missed += any && !isKept[i / PointChunks::kPoints];
            }
            EXPECT_EQ(missed, 0u) << "gaze " << gaze.x << ", " << gaze.y << " move " << siteMove;
        }
    }
}

TEST(PointChunks, TheGazeInACornerSkipsMostOfTheSet) {
    const foveation::PointSet set = smallSet();
    const PointChunks chunks(set);
    const glm::vec2 off = foveation::gazeOffset({160.0f, 144.0f}, 160, 144);
    const std::size_t onScreen = set.countOnScreen(160.0f, 144.0f, foveation::kSampleMargin);
    const std::size_t kept = chunks.onScreen(off, 160, 144, foveation::kSampleMargin, 0.0f).size() *
                             PointChunks::kPoints;
    // Table 1: about 27 % of the set lands on screen with the gaze in a corner. Chunks that
    // straddle the screen's edges add some: the kept chunks hold at most 1.5x the points that
    // land.
    EXPECT_GE(kept, onScreen);
    EXPECT_LT(static_cast<double>(kept), 1.5 * static_cast<double>(onScreen));
    EXPECT_LT(kept, set.points().size() / 2);
}

} // namespace
} // namespace gt
