#include "background_point_sets.hpp"

#include <chrono>
#include <cmath>

namespace gt::app {

PointSetKey pointSetKey(const foveation::PointSetParams& params) {
    const foveation::DisplayProfile& d = params.display;
    return {d.width, d.height, std::lround(d.viewingDistance * 1e4), params.scale};
}

std::optional<foveation::CachedPointSet>
BackgroundPointSets::take(const foveation::PointSetParams& params, bool wait) {
    const PointSetKey key = pointSetKey(params);
    auto it = mBuilds.find(key);
    if (it == mBuilds.end()) {
        // One set at a time: a window dragged through many sizes must not start one for each.
        // The caller asks again next frame, with the size it has then.
        if (!wait && busy()) return std::nullopt;
        // std::async with launch::async: a thread of its own, joined by the future.
        it = mBuilds
                 .emplace(key, std::async(std::launch::async,
                                          [dir = mCacheDir, params] {
                                              return foveation::loadOrGenerate(dir, params);
                                          }))
                 .first;
    }
    if (!wait && it->second.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
        return std::nullopt;
    }
    foveation::CachedPointSet ready = it->second.get(); // rethrows the worker's exception
    mBuilds.erase(it);
    return ready;
}

bool BackgroundPointSets::busy() const {
    for (const auto& [key, build] : mBuilds) {
        if (build.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return true;
    }
    return false;
}

} // namespace gt::app
