// Build time and bytes of the neighbour structures for the fove eye and a 3840x3744 eye
// (Varjo XR-4 class, 120 deg), figures for docs/point-set.md. Disabled: minutes and gigabytes,
// so the suite skips them; run by hand with
//   gazetrace_unit_tests --gtest_also_run_disabled_tests --gtest_filter='TableScaling.*'
// GT_SCALE_CACHE names the point-set cache directory (default: a directory under /tmp),
// GT_SCALE_THREADS the build threads (default: every core); GT_SCALE_TABLES_ONLY=1 builds only
// the neighbour index and k = 10 table (the MSM build, without the RBF structures).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "foveation/neighbour_index.hpp"
#include "foveation/pixel_knn_table.hpp"
#include "foveation/point_buckets.hpp"
#include "foveation/point_set_cache.hpp"
#include "foveation/rbf_inverse.hpp"
#include "foveation/rbf_pixel_weights.hpp"

namespace gt::foveation {
namespace {

std::filesystem::path cacheDir() {
    const char* dir = std::getenv("GT_SCALE_CACHE");
    return dir != nullptr ? std::filesystem::path(dir)
                          : std::filesystem::temp_directory_path() / "gazetrace-scale-cache";
}

// Processor seconds of this process since the last call: with one build thread, the build's
// own time however loaded the machine is.
double cpuSeconds() {
    static std::clock_t last = std::clock();
    const std::clock_t now = std::clock();
    const double s = static_cast<double>(now - last) / CLOCKS_PER_SEC;
    last = now;
    return s;
}

void report(const std::string& eye, const std::string& what, double seconds, std::size_t bytes) {
    std::printf("%-10s %-28s %8.2f s (cpu %7.2f s) %10.1f MB\n", eye.c_str(), what.c_str(), seconds,
                cpuSeconds(), static_cast<double>(bytes) / 1e6);
    std::fflush(stdout);
    ::testing::Test::RecordProperty(eye + "." + what + ".seconds", std::to_string(seconds));
    ::testing::Test::RecordProperty(eye + "." + what + ".bytes", std::to_string(bytes));
}

// FNV-1a over the table's four arrays.
uint64_t layoutChecksum(const PixelKnnTable& table) {
    uint64_t hash = 1469598103934665603ull;
    auto add = [&](const auto& values) {
        for (const auto v : values) {
            hash = (hash ^ v) * 1099511628211ull;
        }
    };
    add(table.tiles());
    add(table.candidates());
    add(table.slots());
    add(table.pixelRows());
    return hash;
}

void measure(const DisplayProfile& display, bool rbfPixelWeights, std::vector<uint32_t> ks) {
    if (const char* t = std::getenv("GT_SCALE_THREADS")) {
        detail::setBuildThreads(static_cast<unsigned>(std::atoi(t)));
    }
    PointSetParams params;
    params.display = display;
    (void)cpuSeconds();
    const CachedPointSet cached = loadOrGenerate(cacheDir(), params);
    const PointSet& set = cached.set;
    const std::string eye = display.name;
    report(eye, cached.fromCache ? "point set (cache load)" : "point set (generated)",
           cached.seconds, set.points().size() * sizeof(Point));
    std::printf("%-10s %zu points, canvas %ux%u\n", eye.c_str(), set.points().size(),
                set.canvasWidth(), set.canvasHeight());
    const NeighbourIndex index(set, NeighbourIndex::kMaxNeighbours);
    report(eye, "neighbour index k=20", index.buildSeconds(), index.bytes());
    std::printf("%-10s   of which the nearest point per pixel %.2f s\n", eye.c_str(),
                index.nearest().buildSeconds());
    if (std::getenv("GT_SCALE_TABLES_ONLY") != nullptr) {
        rbfPixelWeights = false;
        ks = {10u};
    } else {
        const RbfInverse inverse =
            buildRbfInverse(set, index, 10, RbfKernelType::Multiquadric, 1.0f);
        report(eye, "rbf inverse k=10", inverse.seconds, inverse.inverse.size() * sizeof(float));
    }
    const std::size_t canvas = std::size_t{set.canvasWidth()} * set.canvasHeight();
    for (uint32_t k : ks) {
        const PixelKnnTable table(set, index, k);
        report(eye, "pixel knn table k=" + std::to_string(k), table.buildSeconds(), table.bytes());
        std::printf("%-10s   %zu rows, %zu candidates, %u-byte slots; flat: %.1f MB\n", eye.c_str(),
                    table.rows(), table.candidates().size(), table.slotBytes(),
                    static_cast<double>(table.flatBytes()) / 1e6);
        // A faster build must build the same table: compare this with the previous build's.
        std::printf("%-10s   layout checksum %016llx\n", eye.c_str(),
                    static_cast<unsigned long long>(layoutChecksum(table)));
        if (k == 10) {
            // Modified Shepard with the table, CPU and GPU together: the set and the index
            // (CPU), the points (RGBA32F), nearest point per pixel, lists and table (GPU).
            const std::size_t n = set.points().size();
            const std::size_t total = n * sizeof(Point) + index.bytes() + n * 16 + canvas * 4 +
                                      index.neighbours().size() * 4 + table.bytes();
            std::printf("%-10s msm k=10 method memory: %.1f MB (index and table %.2f s)\n",
                        eye.c_str(), static_cast<double>(total) / 1e6,
                        index.buildSeconds() + table.buildSeconds());
        }
        if ((rbfPixelWeights || std::getenv("GT_SCALE_RBF") != nullptr) && k == 10) {
            const RbfPixelWeights weights(set, table, RbfKernelType::Multiquadric, 1.0f);
            report(eye, "rbf pixel weights k=10", weights.buildSeconds(), weights.bytes());
        }
    }
}

TEST(TableScaling, DISABLED_Fove) {
    measure(displayProfile(DisplayModel::Fove), true, {10u, 20u});
}

TEST(TableScaling, DISABLED_Varjo3840x3744) {
    measure(fovDisplayProfile("varjo-xr4", 3840, 3744, 120.0), false, {10u, 20u});
}

} // namespace
} // namespace gt::foveation
