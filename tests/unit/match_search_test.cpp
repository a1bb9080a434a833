// eval --match's search on synthetic scores whose answers are known: a monotone threshold, a
// search that starts above it, no match at all, and per-band scores with bounded noise.
#include <array>
#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "match_search.hpp"

namespace gt::app {
namespace {

// Every candidate at most once, and the result's bracket made of tried candidates.
void expectConsistent(const MatchSearchResult& r, const std::function<bool(uint32_t)>& truth) {
    std::set<uint32_t> seen;
    for (const MatchTry& t : r.tried) {
        EXPECT_TRUE(seen.insert(t.candidate).second) << "tried twice: " << t.candidate;
        EXPECT_EQ(t.matches, truth(t.candidate)) << t.candidate;
    }
    if (r.match) {
        EXPECT_TRUE(seen.contains(*r.match));
        EXPECT_TRUE(truth(*r.match));
    }
    if (r.below != 0) {
        EXPECT_TRUE(seen.contains(r.below));
        EXPECT_FALSE(truth(r.below));
    }
}

TEST(MatchSearch, EveryBandMustBeNoWorse) {
    const std::array<double, 4> target{0.10, 0.05, 0.04, 0.02};
    EXPECT_TRUE(noWorseInEveryBand(target, target));
    EXPECT_TRUE(noWorseInEveryBand(std::array{0.09, 0.05, 0.01, 0.0}, target));
    EXPECT_FALSE(noWorseInEveryBand(std::array{0.01, 0.01, 0.01, 0.021}, target));
    EXPECT_FALSE(noWorseInEveryBand(std::array{0.11, 0.01, 0.01, 0.01}, target));
    EXPECT_FALSE(noWorseInEveryBand(std::array{0.01, 0.01, std::nan(""), 0.01}, target));
}

TEST(MatchSearch, MonotoneThresholdFoundExactly) {
    const auto truth = [](uint32_t n) { return n >= 777; };
    const MatchSearchResult r = findLowestMatch(
        {.lowest = 1, .highest = 1280, .start = 604, .tolerance = 0.0, .maxTries = 32}, truth);
    ASSERT_TRUE(r.match);
    EXPECT_EQ(*r.match, 777u);
    EXPECT_EQ(r.below, 776u);
    EXPECT_TRUE(r.converged);
    EXPECT_EQ(r.tried[0].candidate, 604u);
    EXPECT_EQ(r.tried[1].candidate, 1208u); // one step up by the growth factor
    expectConsistent(r, truth);
}

TEST(MatchSearch, ToleranceAndBudgetBoundTheTries) {
    const auto truth = [](uint32_t n) { return n >= 900; };
    const MatchSearchResult r = findLowestMatch(
        {.lowest = 1, .highest = 1280, .start = 800, .tolerance = 0.01, .maxTries = 8}, truth);
    ASSERT_TRUE(r.match);
    EXPECT_TRUE(r.converged);
    EXPECT_LE(r.tried.size(), 8u);
    EXPECT_GE(*r.match, 900u);
    EXPECT_LT(r.below, 900u);
    EXPECT_LE(static_cast<double>(*r.match), 1.01 * r.below);
    expectConsistent(r, truth);

    // Too small a budget: the best match so far, not converged.
    const MatchSearchResult cut = findLowestMatch(
        {.lowest = 1, .highest = 1280, .start = 604, .tolerance = 0.0, .maxTries = 4}, truth);
    EXPECT_EQ(cut.tried.size(), 4u);
    EXPECT_FALSE(cut.converged);
    ASSERT_TRUE(cut.match);
    EXPECT_GT(*cut.match, 900u);
}

TEST(MatchSearch, StartingAboveTheAnswerStepsDown) {
    const auto truth = [](uint32_t n) { return n >= 100; };
    const MatchSearchResult r = findLowestMatch(
        {.lowest = 1, .highest = 1280, .start = 604, .tolerance = 0.0, .maxTries = 32}, truth);
    ASSERT_TRUE(r.match);
    EXPECT_EQ(*r.match, 100u);
    EXPECT_EQ(r.below, 99u);
    EXPECT_EQ(r.tried[1].candidate, 302u);
    expectConsistent(r, truth);

    // Rays per pixel: everything matches, so the lowest is the answer.
    const MatchSearchResult all = findLowestMatch(
        {.lowest = 1, .highest = 4, .start = 2, .tolerance = 0.0}, [](uint32_t) { return true; });
    ASSERT_TRUE(all.match);
    EXPECT_EQ(*all.match, 1u);
    EXPECT_EQ(all.below, 0u);
    EXPECT_TRUE(all.converged);
}

TEST(MatchSearch, NoMatchWhenEvenTheHighestFails) {
    const auto truth = [](uint32_t n) { return n > 4; };
    const MatchSearchResult r =
        findLowestMatch({.lowest = 1, .highest = 4, .start = 1, .tolerance = 0.0}, truth);
    EXPECT_FALSE(r.match);
    EXPECT_EQ(r.below, 4u);
    EXPECT_TRUE(r.converged);
    ASSERT_EQ(r.tried.size(), 3u); // 1, 2, 4
    EXPECT_EQ(r.tried.back().candidate, 4u);
    expectConsistent(r, truth);
}

// Four bands of error falling as 1/n^2 (pixels), each with a deterministic noise of up to 3 %:
// the target is crossed at n = 1000 without noise, so every candidate outside
// [1000 sqrt(0.97), 1000 sqrt(1.03)] = [985, 1015] is decided by the trend alone.
TEST(MatchSearch, NoisyBandsLandWhereTheNoiseAllows) {
    const std::array<double, 4> target{0.08, 0.05, 0.03, 0.01};
    const auto scores = [&](uint32_t n) {
        std::array<double, 4> s{};
        for (std::size_t b = 0; b < 4; ++b) {
            const double noise = std::sin(12.9898 * n + 78.233 * static_cast<double>(b));
            const double trend = 1e6 / (static_cast<double>(n) * n);
            s[b] = target[b] * trend * (1.0 + 0.03 * noise);
        }
        return s;
    };
    const auto truth = [&](uint32_t n) { return noWorseInEveryBand(scores(n), target); };
    // The noise really makes the outcome non-monotone near the crossing.
    int flips = 0;
    for (uint32_t n = 985; n < 1015; ++n) {
        flips += truth(n) != truth(n + 1) ? 1 : 0;
    }
    ASSERT_GT(flips, 1);
    for (const uint32_t start : {300u, 604u, 1100u, 2000u}) {
        const MatchSearchResult r = findLowestMatch(
            {.lowest = 1, .highest = 2560, .start = start, .tolerance = 0.0, .maxTries = 40},
            truth);
        ASSERT_TRUE(r.match) << start;
        EXPECT_TRUE(r.converged);
        // A change of outcome, one apart, inside the band the noise can reach.
        EXPECT_EQ(r.below + 1, *r.match) << start;
        EXPECT_GE(*r.match, 985u) << start;
        EXPECT_LE(*r.match, 1015u) << start;
        expectConsistent(r, truth);
    }
}

// A synthetic path tracer whose error falls with pixels and with paths per pixel: a candidate
// of width n at r rays per pixel matches when n^2 * r >= 1200^2 * 8 and n >= 900 (a fovea only
// 8 paths per pixel reach). At 4 rays per pixel even the full 1280 fails; at 8 the lowest
// width is 1200; the search never goes to 16.
TEST(MatchSearch, DoublesTheRaysPerPixelWhenFullSizeDoesNotMatch) {
    const auto truth = [](uint32_t n, uint32_t r) {
        return n >= 900 && static_cast<uint64_t>(n) * n * r >= 1200ull * 1200 * 8;
    };
    std::set<uint32_t> rates;
    const RaysMatchResult r = findLowestMatchDoublingRays(
        {.lowest = 1, .highest = 1280, .start = 604, .tolerance = 0.0, .maxTries = 32}, 4, 3,
        [&](uint32_t n, uint32_t rpp) {
            rates.insert(rpp);
            return truth(n, rpp);
        });
    ASSERT_TRUE(r.search.match);
    EXPECT_EQ(r.raysPerPixel, 8u);
    EXPECT_EQ(*r.search.match, 1200u);
    EXPECT_EQ(r.search.tried.front().candidate, 1280u); // the doubled search starts at full size
    EXPECT_EQ(rates, (std::set<uint32_t>{4u, 8u}));
    // No doublings allowed: no match.
    EXPECT_FALSE(findLowestMatchDoublingRays(
                     {.lowest = 1, .highest = 1280, .start = 604, .tolerance = 0.0, .maxTries = 32},
                     4, 0, truth)
                     .search.match);
}

} // namespace
} // namespace gt::app
