// Fuzz target: the point-set cache reader, then the neighbour search every loaded set feeds.
// The input is a cache file without its trailing checksum; the harness appends the right one,
// so mutations get past the checksum to the content checks (a file with a valid
// checksum and NaN or 1e30 points sent the neighbour search into an unbounded loop).
// Contract (point_set_cache.hpp): a file that cannot be used is reported, never thrown, and
// never crashes; a set that loads has its points on the canvas, and every query answers.
#include <cstring>
#include <vector>

#include "fuzz_input.hpp"
#include "fuzz_params.hpp"

#include "foveation/neighbour_index.hpp"
#include "foveation/point_set_cache.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using gt::fuzz::finding;
    std::vector<std::uint8_t> bytes(data, data + size);
    const std::uint64_t sum = gt::foveation::pointSetChecksum(bytes);
    bytes.resize(size + sizeof(sum));
    std::memcpy(bytes.data() + size, &sum, sizeof(sum));
    const auto file = gt::fuzz::InputFile::write(bytes, "points.gtps");
    const auto params = gt::fuzz::pointSetParams();
    const gt::foveation::CacheLoad loaded = gt::foveation::loadPointSet(file, params);
    if (!loaded.set) {
        if (loaded.problem.empty()) finding("a rejected file with no reason");
        return 0;
    }
    const gt::foveation::PointSet& set = *loaded.set;
    if (set.points().size() < 2) finding("a set of fewer than two points loaded");
    const gt::foveation::NeighbourIndex index(set, 10);
    for (const auto& [x, y] :
         {std::pair{0.5f, 0.5f}, std::pair{64.0f, 48.0f}, std::pair{127.5f, 95.5f}}) {
        const auto nearest = index.query(x, y, 10);
        if (nearest.empty()) finding("a query found no point");
        for (const std::uint32_t i : nearest) {
            if (i >= set.points().size()) finding("a query named a point that does not exist");
        }
    }
    return 0;
}
