// The point-set cache is never trusted when damaged or stale.
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "foveation/point_set_cache.hpp"
#include "support/gltf_fixtures.hpp"
#include "support/gpu_test_context.hpp"
#include "support/writerless_fifo.hpp"

namespace gt::foveation {
namespace {

PointSetParams params(double scale = 1.0) {
    PointSetParams p;
    p.display = {"tiny", 96, 80, 0.85};
    p.scale = scale;
    return p;
}

std::vector<uint8_t> readBytes(const std::filesystem::path& f) {
    std::ifstream in(f, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void flipByte(const std::filesystem::path& f, std::size_t offset) {
    std::fstream io(f, std::ios::in | std::ios::out | std::ios::binary);
    io.seekg(static_cast<std::streamoff>(offset));
    char c = 0;
    io.read(&c, 1);
    c = static_cast<char>(c ^ 0x5A);
    io.seekp(static_cast<std::streamoff>(offset));
    io.write(&c, 1);
}

TEST(PointSetCache, RoundTripsAndIsUsed) {
    const auto dir = test::tempDir("psc");
    const CachedPointSet first = loadOrGenerate(dir, params());
    EXPECT_FALSE(first.fromCache);
    EXPECT_TRUE(first.warning.empty());
    const CachedPointSet second = loadOrGenerate(dir, params());
    EXPECT_TRUE(second.fromCache);
    ASSERT_EQ(first.set.points().size(), second.set.points().size());
    for (std::size_t i = 0; i < first.set.points().size(); ++i) {
        ASSERT_EQ(first.set.points()[i].x, second.set.points()[i].x);
        ASSERT_EQ(first.set.points()[i].spacing, second.set.points()[i].spacing);
    }
}

TEST(PointSetCache, CorruptFileIsRegeneratedWithWarning) {
    const auto dir = test::tempDir("psc_corrupt");
    const CachedPointSet good = loadOrGenerate(dir, params());
    const auto file = cacheFile(dir, params());
    flipByte(file, std::filesystem::file_size(file) / 2);
    const CachedPointSet again = loadOrGenerate(dir, params());
    EXPECT_FALSE(again.fromCache);
    EXPECT_NE(again.warning.find("corrupt"), std::string::npos) << again.warning;
    EXPECT_EQ(again.set.points().size(), good.set.points().size());
    EXPECT_TRUE(loadOrGenerate(dir, params()).fromCache); // rewritten, good again
}

TEST(PointSetCache, TruncatedWrongMagicAndStaleFilesAreRejected) {
    const auto dir = test::tempDir("psc_bad");
    (void)loadOrGenerate(dir, params());
    const auto file = cacheFile(dir, params());
    const auto size = std::filesystem::file_size(file);
    std::filesystem::resize_file(file, size / 3);
    EXPECT_FALSE(loadPointSet(file, params()).set.has_value());
    {
        std::ofstream f(file, std::ios::binary);
        f << "not a point set at all";
    }
    const CacheLoad junk = loadPointSet(file, params());
    EXPECT_FALSE(junk.set.has_value());
    EXPECT_NE(junk.problem.find("not a gazetrace point-set file"), std::string::npos);
    // A valid file made with other parameters is stale.
    const CachedPointSet other = loadOrGenerate(dir, params(2.0));
    const CacheLoad stale = loadPointSet(cacheFile(dir, params(2.0)), params(1.0));
    EXPECT_FALSE(stale.set.has_value());
    EXPECT_NE(stale.problem.find("stale"), std::string::npos) << stale.problem;
    EXPECT_NE(cacheFile(dir, params(1.0)), cacheFile(dir, params(2.0)));
    EXPECT_FALSE(other.set.points().empty());
}

// A cache whose checksum is right but whose points are NaN, far away, or too few
// was trusted (the neighbour search then ran unbounded; 0 or 1 points failed every later run).
// Its contents are checked now: loadOrGenerate warns, regenerates and rewrites it.
TEST(PointSetCache, ChecksItsContentsNotOnlyItsChecksum) {
    const auto dir = test::tempDir("psc_contents");
    const PointSetParams p = params();
    const PointSet good = PointSet::generate(p);
    const auto file = cacheFile(dir, p);
    // A file with a valid checksum and one field of point i replaced, as a hostile or broken
    // writer would leave it (fromPoints refuses such points, so the bytes are edited).
    savePointSet(file, good);
    const std::vector<uint8_t> saved = readBytes(file);
    const std::size_t firstPoint = saved.size() - 8 - 12 * good.points().size();
    auto saveWith = [&](std::size_t i, int field, float value) {
        std::vector<uint8_t> b = saved;
        std::memcpy(b.data() + firstPoint + 12 * i + 4 * static_cast<std::size_t>(field), &value,
                    4);
        const uint64_t sum = pointSetChecksum(std::span(b).first(b.size() - 8));
        std::memcpy(b.data() + b.size() - 8, &sum, 8);
        test::writeFile(file, b.data(), b.size());
    };
    saveWith(7, 0, std::numeric_limits<float>::quiet_NaN());
    EXPECT_NE(loadPointSet(file, p).problem.find("lies outside the canvas"), std::string::npos);
    saveWith(3, 1, good.points()[3].y * 1e30f);
    EXPECT_NE(loadPointSet(file, p).problem.find("lies outside the canvas"), std::string::npos);
    saveWith(5, 2, std::numeric_limits<float>::infinity());
    EXPECT_NE(loadPointSet(file, p).problem.find("impossible spacing"), std::string::npos);
    savePointSet(file, PointSet::fromPoints(p, {good.points().front()}));
    EXPECT_NE(loadPointSet(file, p).problem.find("1 point(s)"), std::string::npos);
    // The fuzz target's 2-point seed loaded and failed in the neighbour index; 21 points are the
    // fewest a 20-neighbour query can use, and a set that covers a tenth of the canvas has
    // lost points.
    savePointSet(file, PointSet::fromPoints(p, {good.points().begin(), good.points().begin() + 2}));
    EXPECT_NE(loadPointSet(file, p).problem.find("2 point(s)"), std::string::npos);
    const std::size_t tenth = good.points().size() / 10;
    savePointSet(file, PointSet::fromPoints(p, {good.points().begin(),
                                                good.points().begin() + static_cast<long>(tenth)}));
    EXPECT_NE(loadPointSet(file, p).problem.find("cover too little of the canvas"),
              std::string::npos)
        << loadPointSet(file, p).problem;
    EXPECT_THROW((void)PointSet::fromPoints(p, {{std::numeric_limits<float>::quiet_NaN(), 1, 1}}),
                 ArgumentError);
    // Regenerated and rewritten: the next load trusts the file again.
    const CachedPointSet again = loadOrGenerate(dir, p);
    EXPECT_FALSE(again.fromCache);
    EXPECT_NE(again.warning.find("regenerating"), std::string::npos);
    EXPECT_EQ(again.set.points().size(), good.points().size());
    EXPECT_TRUE(loadPointSet(file, p).set.has_value());
    // A folder where the file should be: a warning and a fresh set, not a crash.
    std::filesystem::remove(file);
    std::filesystem::create_directories(file);
    const CachedPointSet folder = loadOrGenerate(dir, p);
    EXPECT_NE(folder.warning.find("a folder"), std::string::npos) << folder.warning;
    EXPECT_EQ(folder.set.points().size(), good.points().size());
}

// A FIFO where the cache file should be blocked every run forever. It is refused without being
// opened for reading, the set regenerated, and the FIFO replaced by a good cache file.
TEST(PointSetCache, AFifoOrADeviceIsRefusedAndLeftAsItWas) {
    const auto dir = test::tempDir("psc_fifo");
    const PointSetParams p = params();
    const auto file = cacheFile(dir, p);
    {
        const test::WriterlessFifo fifo(file);
        const CachedPointSet c = loadOrGenerate(dir, p);
        EXPECT_FALSE(c.fromCache);
        EXPECT_NE(c.warning.find(file.string() + ": a FIFO"), std::string::npos) << c.warning;
        EXPECT_FALSE(fifo.blockedALoader());
        EXPECT_FALSE(c.set.points().empty());
        // The one output rule: a file that is not a regular file is never replaced, so the
        // cache is not written and the warning says so.
        EXPECT_NE(c.warning.find("not a regular file; refusing to replace it"), std::string::npos)
            << c.warning;
        EXPECT_TRUE(std::filesystem::is_fifo(file));
    }
    std::filesystem::remove(file);
    EXPECT_FALSE(loadOrGenerate(dir, p).fromCache);
    EXPECT_TRUE(loadOrGenerate(dir, p).fromCache);
    std::filesystem::create_symlink("/dev/zero", dir / "device.gtps");
    const CacheLoad device = loadPointSet(dir / "device.gtps", p);
    EXPECT_FALSE(device.set.has_value());
    EXPECT_NE(device.problem.find("a character device"), std::string::npos) << device.problem;
}

} // namespace
} // namespace gt::foveation
