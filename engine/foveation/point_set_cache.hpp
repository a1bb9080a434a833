#pragma once
// On-disk cache of generated point sets. Binary, little-endian, versioned:
//   "GTPS" | u32 version | parameters (every input of generate()) | u64 count |
//   count x (f32 x, f32 y, f32 spacing) | u64 FNV-1a checksum of everything before it.
// A file that is truncated, fails its checksum, has another version or was made with other
// parameters is never trusted: load() reports why, and loadOrGenerate() warns, regenerates
// and rewrites it. Files are written under a temporary name and renamed when complete.
#include <filesystem>
#include <optional>
#include <span>
#include <string>

#include "foveation/point_set.hpp"

namespace gt::foveation {

inline constexpr uint32_t kPointSetCacheVersion = 1;

struct CacheLoad {
    std::optional<PointSet> set;
    std::string problem; // why the file was not used, when set is empty
};

// FNV-1a 64 of a cache file's bytes before its trailing checksum: what save writes and load
// compares (the fuzz target forges valid checksums with it to reach the content checks).
[[nodiscard]] uint64_t pointSetChecksum(std::span<const uint8_t> bytes) noexcept;

[[nodiscard]] CacheLoad loadPointSet(const std::filesystem::path& file,
                                     const PointSetParams& params);
void savePointSet(const std::filesystem::path& file, const PointSet& set);

// The cache file name for these parameters (a hash of all of them) inside `dir`.
[[nodiscard]] std::filesystem::path cacheFile(const std::filesystem::path& dir,
                                              const PointSetParams& params);

struct CachedPointSet {
    PointSet set;
    bool fromCache = false;
    std::string warning; // set when an existing cache file was rejected
    double seconds = 0.0;
    std::string thinned; // loadOrGenerateForView: set when the set was thinned, and how
};

[[nodiscard]] CachedPointSet loadOrGenerate(const std::filesystem::path& dir,
                                            const PointSetParams& params,
                                            const PointSet::Progress& progress = {});

// The set a view of params.display traces (point_set_cap.hpp): `params`' own set when no
// whole-pixel gaze traces more of its points than the screen has pixels, else the same set
// thinned by the first of spacingFloors() whose set keeps to that. Each set is cached under
// its own parameters (a thinned set's include its floor), so a thinned set is never taken for
// the unthinned one, and a set that keeps to the cap keeps its file.
[[nodiscard]] CachedPointSet loadOrGenerateForView(const std::filesystem::path& dir,
                                                   const PointSetParams& params,
                                                   const PointSet::Progress& progress = {});

} // namespace gt::foveation
