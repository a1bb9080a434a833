#include "foveation/point_set_cache.hpp"

#include <span>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

#include "atomic_write.hpp"
#include "core/error.hpp"
#include "foveation/neighbour_index.hpp"
#include "input_file.hpp"
#include "limits.hpp"

namespace gt::foveation {

namespace {

constexpr char kMagic[4] = {'G', 'T', 'P', 'S'};

uint64_t fnv1a(const uint8_t* data, std::size_t n, uint64_t h = 1469598103934665603ull) {
    for (std::size_t i = 0; i < n; ++i) {
        h ^= data[i];
        h *= 1099511628211ull;
    }
    return h;
}

class Writer {
public:
    template <typename T> void put(const T& v) {
        const auto* p = reinterpret_cast<const uint8_t*>(&v);
        bytes.insert(bytes.end(), p, p + sizeof(T));
    }
    std::vector<uint8_t> bytes;
};

class Reader {
public:
    explicit Reader(std::span<const uint8_t> b) : mBytes(b) {}
    template <typename T> bool get(T& v) {
        if (mPos + sizeof(T) > mBytes.size()) return false;
        std::memcpy(&v, mBytes.data() + mPos, sizeof(T));
        mPos += sizeof(T);
        return true;
    }
    [[nodiscard]] std::size_t pos() const { return mPos; }

private:
    std::span<const uint8_t> mBytes;
    std::size_t mPos = 0;
};

// Every input of PointSet::generate, in a fixed order.
void putParams(Writer& w, const PointSetParams& p) {
    const ContrastSensitivity csf;
    w.put(p.display.width);
    w.put(p.display.height);
    w.put(p.display.viewingDistance);
    w.put(p.scale);
    w.put(p.seed);
    w.put(p.dartsPerCanvasPixel);
    w.put(p.dartsPerCentrePixel);
    w.put(csf.ct0);
    w.put(csf.alpha);
    w.put(csf.e2);
}

} // namespace

uint64_t pointSetChecksum(std::span<const uint8_t> bytes) noexcept {
    return fnv1a(bytes.data(), bytes.size());
}

CacheLoad loadPointSet(const std::filesystem::path& file, const PointSetParams& params) {
    // A regular file of bounded size only (a FIFO in the cache folder blocked forever); what
    // is refused here is regenerated and written over by loadOrGenerate.
    std::string text;
    try {
        text = io::readInputFile(file, io::limits::kCacheFileBytes);
    } catch (const io::InputError& e) {
        return {std::nullopt, e.what()};
    }
    const std::span<const uint8_t> bytes(reinterpret_cast<const uint8_t*>(text.data()),
                                         text.size());
    if (bytes.size() < 4 + 4 + 8 || std::memcmp(bytes.data(), kMagic, 4) != 0) {
        return {std::nullopt, file.string() + " is not a gazetrace point-set file"};
    }
    if (bytes.size() < 8) return {std::nullopt, file.string() + " is truncated"};
    uint64_t stored = 0;
    std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
    if (fnv1a(bytes.data(), bytes.size() - 8) != stored) {
        return {std::nullopt, file.string() + " is corrupt (checksum mismatch)"};
    }
    Reader r(bytes);
    char magic[4];
    uint32_t version = 0;
    r.get(magic);
    r.get(version);
    if (version != kPointSetCacheVersion) {
        return {std::nullopt, file.string() + " has version " + std::to_string(version) +
                                  ", expected " + std::to_string(kPointSetCacheVersion)};
    }
    Writer expected;
    putParams(expected, params);
    if (bytes.size() < r.pos() + expected.bytes.size() ||
        std::memcmp(bytes.data() + r.pos(), expected.bytes.data(), expected.bytes.size()) != 0) {
        return {std::nullopt, file.string() + " was made with other parameters (stale)"};
    }
    std::vector<uint8_t> skip(expected.bytes.size());
    for (auto& b : skip)
        r.get(b);
    uint64_t count = 0;
    if (!r.get(count) || count > (bytes.size() - r.pos()) / 12) {
        return {std::nullopt, file.string() + " is truncated"};
    }
    if (r.pos() + count * 12 + 8 != bytes.size()) {
        return {std::nullopt, file.string() + " has the wrong size"};
    }
    // A valid checksum says the bytes are what was written, not that they make sense: a
    // NaN or far-away point sent the neighbour search into an unbounded loop.
    // Every consumer asks for up to kMaxNeighbours neighbours of a point (the fuzz target's
    // 2-point seed loaded, then failed in the neighbour index, as it would have every run).
    if (count <= NeighbourIndex::kMaxNeighbours) {
        return {std::nullopt, file.string() + " holds " + std::to_string(count) +
                                  " point(s); a point set has many"};
    }
    const float canvasW = 2.0f * static_cast<float>(params.display.width);
    const float canvasH = 2.0f * static_cast<float>(params.display.height);
    const float maxSpacing = canvasW + canvasH;
    // A dart-thrown set is maximal: discs of radius p around its points cover the canvas, so
    // the sum of p^2 is at least canvas / pi (generated sets reach 0.45 to 0.9 of the canvas).
    // Far less means points are missing: holes the interpolation would smear over.
    double covered = 0.0;
    std::vector<Point> pts(count);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        Point& p = pts[i];
        r.get(p.x);
        r.get(p.y);
        r.get(p.spacing);
        // Thesis eq. (4): p >= 1 - (1 - sqrt(1/pi)) = 0.564 pixels, and far less than the canvas.
        if (!(p.spacing >= 0.5f && p.spacing <= maxSpacing)) {
            return {std::nullopt, file.string() + ": point " + std::to_string(i) +
                                      " has an impossible spacing " + std::to_string(p.spacing)};
        }
        covered += static_cast<double>(p.spacing) * p.spacing;
    }
    if (covered < 0.1 * static_cast<double>(canvasW) * canvasH) {
        return {std::nullopt, file.string() + ": its " + std::to_string(count) +
                                  " points cover too little of the canvas (points are missing)"};
    }
    // fromPoints checks that every point lies on the canvas (NaN and 1e30 do not).
    try {
        return {PointSet::fromPoints(params, std::move(pts)), {}};
    } catch (const ArgumentError& e) {
        return {std::nullopt, file.string() + ": " + e.what()};
    }
}

void savePointSet(const std::filesystem::path& file, const PointSet& set) {
    Writer w;
    for (char c : kMagic)
        w.put(c);
    w.put(kPointSetCacheVersion);
    putParams(w, set.params());
    w.put(static_cast<uint64_t>(set.points().size()));
    for (const Point& p : set.points()) {
        w.put(p.x);
        w.put(p.y);
        w.put(p.spacing);
    }
    w.put(fnv1a(w.bytes.data(), w.bytes.size()));
    std::error_code ec;
    if (!file.parent_path().empty()) std::filesystem::create_directories(file.parent_path(), ec);
    try {
        io::writeFileAtomic(file, std::as_bytes(std::span(w.bytes)));
    } catch (const io::WriteError& e) {
        throw Error(std::string("point set: ") + e.what());
    }
}

std::filesystem::path cacheFile(const std::filesystem::path& dir, const PointSetParams& params) {
    Writer w;
    w.put(kPointSetCacheVersion);
    putParams(w, params);
    const uint64_t h = fnv1a(w.bytes.data(), w.bytes.size());
    char name[64];
    std::snprintf(name, sizeof(name), "pointset-%ux%u-%016llx.gtps", params.display.width,
                  params.display.height, static_cast<unsigned long long>(h));
    return dir / name;
}

CachedPointSet loadOrGenerate(const std::filesystem::path& dir, const PointSetParams& params,
                              const PointSet::Progress& progress) {
    const auto start = std::chrono::steady_clock::now();
    const std::filesystem::path file = cacheFile(dir, params);
    CachedPointSet out;
    std::error_code ec;
    if (std::filesystem::exists(file, ec)) {
        CacheLoad loaded = loadPointSet(file, params);
        if (loaded.set) {
            out.set = std::move(*loaded.set);
            out.fromCache = true;
            out.seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            return out;
        }
        out.warning = loaded.problem + "; regenerating";
    }
    out.set = PointSet::generate(params, progress);
    try {
        savePointSet(file, out.set);
    } catch (const Error& e) {
        out.warning += (out.warning.empty() ? "" : "; ") + std::string(e.what());
    }
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

} // namespace gt::foveation
