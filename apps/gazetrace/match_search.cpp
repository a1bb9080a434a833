#include "match_search.hpp"

#include <algorithm>
#include <cmath>

namespace gt::app {

bool noWorseInEveryBand(std::span<const double> candidate, std::span<const double> target) {
    if (candidate.size() != target.size()) {
        return false;
    }
    for (std::size_t b = 0; b < target.size(); ++b) {
        if (!(candidate[b] <= target[b])) {
            return false;
        }
    }
    return true;
}

namespace {

uint32_t clampTo(double n, const MatchSearchLimits& l) {
    return static_cast<uint32_t>(
        std::clamp(std::lround(n), static_cast<long>(l.lowest), static_cast<long>(l.highest)));
}

bool closed(uint32_t lo, uint32_t hi, double tolerance) {
    return hi <= lo + 1 || static_cast<double>(hi) <= static_cast<double>(lo) * (1.0 + tolerance);
}

} // namespace

MatchSearchResult findLowestMatch(const MatchSearchLimits& limits,
                                  const std::function<bool(uint32_t)>& matches) {
    MatchSearchResult r;
    const auto tryOne = [&](uint32_t n) {
        const bool m = matches(n);
        r.tried.push_back({n, m});
        return m;
    };
    const auto budgetLeft = [&] { return r.tried.size() < limits.maxTries; };
    uint32_t n = std::clamp(limits.start, limits.lowest, limits.highest);
    uint32_t lo = 0, hi = 0; // lo: a non-match (0: none yet), hi: a match (0: none yet)
    if (tryOne(n)) {
        hi = n;
        // Down by `growth` until a candidate fails or the lowest matches.
        while (hi > limits.lowest && lo == 0 && budgetLeft()) {
            n = std::min(hi - 1, clampTo(static_cast<double>(hi) / limits.growth, limits));
            (tryOne(n) ? hi : lo) = n;
        }
        if (hi == limits.lowest) {
            r.match = hi;
            r.converged = true;
            return r;
        }
    } else {
        lo = n;
        // Up by `growth` until a candidate matches; none when the highest does not.
        while (hi == 0 && lo < limits.highest && budgetLeft()) {
            n = std::max(lo + 1, clampTo(static_cast<double>(lo) * limits.growth, limits));
            (tryOne(n) ? hi : lo) = n;
        }
        if (hi == 0) {
            r.below = lo;
            r.converged = lo == limits.highest;
            return r;
        }
    }
    // Bisect [lo, hi] on a log scale: the candidates are sizes and ray counts.
    while (lo != 0 && !closed(lo, hi, limits.tolerance) && budgetLeft()) {
        const double mid = std::sqrt(static_cast<double>(lo) * static_cast<double>(hi));
        n = std::clamp(static_cast<uint32_t>(std::lround(mid)), lo + 1, hi - 1);
        (tryOne(n) ? hi : lo) = n;
    }
    r.match = hi;
    r.below = lo;
    r.converged = lo != 0 && closed(lo, hi, limits.tolerance);
    return r;
}

RaysMatchResult
findLowestMatchDoublingRays(MatchSearchLimits limits, uint32_t raysPerPixel, uint32_t doublings,
                            const std::function<bool(uint32_t, uint32_t)>& matches) {
    RaysMatchResult r{.raysPerPixel = raysPerPixel};
    for (uint32_t d = 0;; ++d) {
        r.search = findLowestMatch(limits, [&](uint32_t n) { return matches(n, r.raysPerPixel); });
        if (r.search.match || d == doublings) {
            return r;
        }
        r.raysPerPixel *= 2;
        limits.start = limits.highest;
    }
}

} // namespace gt::app
