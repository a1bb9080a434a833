#include "foveation/rbf_inverse.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "foveation/point_buckets.hpp"

namespace gt::foveation {

RbfInverse buildRbfInverse(const PointSet& set, const NeighbourIndex& index, uint32_t k,
                           RbfKernelType kernel, float shape) {
    if (k == 0 || k > index.k() + 1) {
        throw ArgumentError("RBF k must be 1.." + std::to_string(index.k() + 1));
    }
    if (!(shape > 0.0f)) {
        throw ArgumentError("RBF shape c must be positive");
    }
    const auto start = std::chrono::steady_clock::now();
    const auto& pts = set.points();
    RbfInverse out;
    out.k = k;
    out.kernel = kernel;
    out.shape = shape;
    out.inverse.resize(pts.size() * k * k);
    // Chunks of points, so each worker reuses one system's storage across many points.
    constexpr uint32_t kChunk = 1024;
    const auto chunks = static_cast<uint32_t>((pts.size() + kChunk - 1) / kChunk);
    std::atomic<uint32_t> ill{0};
    progress::Step step("inverting the per-point RBF systems", chunks);
    detail::parallelFor(chunks, [&](uint32_t chunk) {
        RbfSystem system(k);
        std::vector<glm::vec2> nb(k);
        std::vector<double> column(k);
        const std::size_t end = std::min<std::size_t>(pts.size(), std::size_t{chunk + 1} * kChunk);
        for (std::size_t q = std::size_t{chunk} * kChunk; q < end; ++q) {
            nb[0] = {pts[q].x, pts[q].y};
            for (uint32_t j = 1; j < k; ++j) {
                const Point& p = pts[index.neighbours()[q * index.k() + j - 1]];
                nb[j] = {p.x, p.y};
            }
            const double c = std::max(1e-3, static_cast<double>(shape) * pts[q].spacing);
            if (!system.factor(nb, kernel, c)) {
                ++ill;
            }
            // Column s of the inverse solves A x = e_s.
            float* dst = &out.inverse[q * k * k];
            for (uint32_t s = 0; s < k; ++s) {
                std::fill(column.begin(), column.end(), 0.0);
                column[s] = 1.0;
                system.solve(column);
                for (uint32_t r = 0; r < k; ++r) {
                    dst[r * k + s] = static_cast<float>(column[r]);
                }
            }
        }
        step.advance();
    });
    out.illConditioned = ill;
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

} // namespace gt::foveation
