// Point sets generated off the frame thread (apps/gazetrace/background_point_sets): the set a
// front end gets is the one generated in place, written to the cache, handed over once, and only
// one set is generated at a time.
#include <chrono>
#include <filesystem>
#include <optional>
#include <thread>

#include <gtest/gtest.h>

#include "background_point_sets.hpp"
#include "foveation/point_set.hpp"
#include "foveation/point_set_cache.hpp"
#include "support/gpu_test_context.hpp"

namespace gt::app {
namespace {

foveation::PointSetParams windowParams(uint32_t w, uint32_t h) {
    foveation::PointSetParams p;
    p.display =
        foveation::windowProfile(foveation::displayProfile(foveation::DisplayModel::Desktop), w, h);
    p.scale = 2.0;
    return p;
}

// Asks every 5 ms, as a frame loop would, until the set is ready (or a minute has passed).
std::optional<foveation::CachedPointSet> pollUntilReady(BackgroundPointSets& sets,
                                                        const foveation::PointSetParams& p) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(1);
    while (std::chrono::steady_clock::now() < deadline) {
        if (auto ready = sets.take(p)) return ready;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return std::nullopt;
}

TEST(BackgroundPointSets, HandsOverTheSetGeneratedInPlaceOnceAndCachesIt) {
    const auto dir = test::tempDir("background_point_sets");
    BackgroundPointSets sets(dir);
    const foveation::PointSetParams p = windowParams(160, 90);
    const std::optional<foveation::CachedPointSet> ready = pollUntilReady(sets, p);
    ASSERT_TRUE(ready.has_value());
    EXPECT_FALSE(sets.pending(p)); // handed over: no longer held
    const foveation::PointSet inPlace = foveation::PointSet::generate(p);
    ASSERT_EQ(ready->set.points().size(), inPlace.points().size());
    for (std::size_t i = 0; i < inPlace.points().size(); ++i) {
        ASSERT_EQ(ready->set.points()[i].x, inPlace.points()[i].x) << i;
        ASSERT_EQ(ready->set.points()[i].y, inPlace.points()[i].y) << i;
    }
    EXPECT_TRUE(std::filesystem::exists(foveation::cacheFile(dir, p)));
    // Asked again (another window of that size later): loaded from the cache, same set.
    const std::optional<foveation::CachedPointSet> again = sets.take(p, true);
    ASSERT_TRUE(again.has_value());
    EXPECT_TRUE(again->fromCache);
    EXPECT_EQ(again->set.points().size(), inPlace.points().size());
}

TEST(BackgroundPointSets, OneSetAtATime) {
    const auto dir = test::tempDir("background_point_sets_one");
    BackgroundPointSets sets(dir);
    const foveation::PointSetParams big = windowParams(640, 360), small = windowParams(64, 36);
    const bool readyAtOnce = sets.take(big).has_value(); // starts it
    ASSERT_FALSE(readyAtOnce) << "a 640x360 set takes longer than starting a thread";
    EXPECT_TRUE(sets.pending(big));
    // While the first is generating, a second size is not started (a window being dragged).
    if (!sets.take(small)) {
        EXPECT_FALSE(sets.pending(small));
    }
    ASSERT_TRUE(sets.take(big, true).has_value());
    EXPECT_FALSE(sets.pending(big));
    // Free again: the second one starts and arrives.
    EXPECT_TRUE(pollUntilReady(sets, small).has_value());
}

} // namespace
} // namespace gt::app
