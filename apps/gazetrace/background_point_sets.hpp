#pragma once
// Point sets generated (or loaded from the cache) on worker threads, so that a front end's frame
// thread never waits for one: the demo after a resize, `xr` before its first frame. The caller
// renders something else (the full-resolution reference) until a set is ready, then builds the
// method from it on its own thread (the GPU buffers and the neighbour index).
#include <cstdint>
#include <filesystem>
#include <future>
#include <map>
#include <optional>
#include <tuple>

#include "foveation/point_set_cache.hpp"

namespace gt::app {

// What tells two point sets apart for a front end: the display's pixels, its viewing distance
// to 1e-4 display widths (a runtime's per-frame float noise in an eye's field of view must not
// rebuild the set) and the scale.
using PointSetKey = std::tuple<uint32_t, uint32_t, long, double>;
[[nodiscard]] PointSetKey pointSetKey(const foveation::PointSetParams& params);

class BackgroundPointSets {
public:
    explicit BackgroundPointSets(std::filesystem::path cacheDir) : mCacheDir(std::move(cacheDir)) {}
    // Waits for the sets still being generated (there is no way to stop one half way).
    ~BackgroundPointSets() = default;
    BackgroundPointSets(const BackgroundPointSets&) = delete;
    BackgroundPointSets& operator=(const BackgroundPointSets&) = delete;

    // The set for `params` once it is ready (handed over once), else nothing: the first call
    // starts it on a worker thread, unless another set is still being generated (then a later
    // call starts it). With `wait`, starts it at once if need be and blocks until it is ready.
    [[nodiscard]] std::optional<foveation::CachedPointSet>
    take(const foveation::PointSetParams& params, bool wait = false);
    // Whether a set for `params` is being generated (started and not yet taken).
    [[nodiscard]] bool pending(const foveation::PointSetParams& params) const {
        return mBuilds.count(pointSetKey(params)) != 0;
    }

private:
    [[nodiscard]] bool busy() const; // a set is still being generated

    std::filesystem::path mCacheDir;
    std::map<PointSetKey, std::future<foveation::CachedPointSet>> mBuilds;
};

} // namespace gt::app
