#pragma once
// `eval --match`'s search: the lowest setting of a uniform render (its width in pixels, or its
// rays per pixel) whose picture is no worse than the foveated frame's. Rendering and scoring a
// candidate is the caller's; this is the bracketing on the ordered candidates, kept pure so
// that it is tested on synthetic scores with known answers.
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace gt::app {

// Whether a candidate's per-band errors are no higher than the target's in every band.
[[nodiscard]] bool noWorseInEveryBand(std::span<const double> candidate,
                                      std::span<const double> target);

struct MatchSearchLimits {
    uint32_t lowest = 1;     // the smallest candidate
    uint32_t highest = 1;    // the largest: full resolution at the foveated rays per point
    uint32_t start = 1;      // the first tried (the candidate that spends the foveated rays)
    double growth = 2.0;     // factor between bracketing steps
    double tolerance = 0.01; // stop when the bracket's ends differ by at most this share
    uint32_t maxTries = 8;   // candidates rendered at most
};

struct MatchTry {
    uint32_t candidate = 0;
    bool matches = false;
};

struct MatchSearchResult {
    std::optional<uint32_t> match; // the lowest matching candidate found; none: no match
    uint32_t below = 0;            // the largest tried candidate under it that did not match
    std::vector<MatchTry> tried;   // in the order tried
    bool converged = false;        // the bracket closed within the tolerance (or to 1 apart)
};

// The error of a candidate falls as it grows (more pixels or rays), not strictly (noise). From
// `start`, steps by `growth` up (no match) or down (a match) until the outcome changes or an
// end is reached, then bisects the bracket geometrically until its ends are within
// `tolerance` of each other or one apart, trying at most `maxTries` candidates. `matches` is
// called once per candidate. No match when even `highest` does not match.
[[nodiscard]] MatchSearchResult findLowestMatch(const MatchSearchLimits& limits,
                                                const std::function<bool(uint32_t)>& matches);

struct RaysMatchResult {
    MatchSearchResult search;  // the last search's
    uint32_t raysPerPixel = 0; // the rays per pixel it ran at
};

// findLowestMatch at `raysPerPixel`; while nothing matches, again at twice the rays per pixel
// (`doublings` times at most), from the highest candidate down. `matches` gets the candidate
// and the rays per pixel.
[[nodiscard]] RaysMatchResult
findLowestMatchDoublingRays(MatchSearchLimits limits, uint32_t raysPerPixel, uint32_t doublings,
                            const std::function<bool(uint32_t, uint32_t)>& matches);

} // namespace gt::app
