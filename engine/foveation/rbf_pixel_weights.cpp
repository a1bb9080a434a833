#include "foveation/rbf_pixel_weights.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "foveation/point_buckets.hpp"

namespace gt::foveation {

RbfPixelWeights::RbfPixelWeights(const PointSet& set, const PixelKnnTable& table,
                                 RbfKernelType kernel, float shape)
    : mK(table.k()), mKernel(kernel), mShape(shape) {
    if (!(shape > 0.0f)) {
        throw ArgumentError("RBF shape c must be positive");
    }
    if (table.canvasWidth() != set.canvasWidth() || table.canvasHeight() != set.canvasHeight()) {
        throw ArgumentError("RBF pixel weights: the k-NN table belongs to another point set");
    }
    const auto start = std::chrono::steady_clock::now();
    const auto& pts = set.points();
    const uint32_t k = mK, width = table.canvasWidth();
    mWeights.resize(static_cast<std::size_t>(width) * table.canvasHeight() * k);
    std::atomic<uint64_t> factorisations{0}, ill{0};
    progress::Step step("solving the per-pixel RBF weights", table.canvasHeight());
    detail::parallelFor(table.canvasHeight(), [&](uint32_t y) {
        RbfSystem system(k);
        std::vector<glm::vec2> nb(k);
        std::vector<double> w(k);
        std::vector<uint32_t> idx(k);
        // The pixel's neighbours in index order, with their places in the table row: the
        // system is factored in this order, so that pixels with the same k points in another
        // distance order (most of a run) share it.
        std::vector<std::pair<uint32_t, uint32_t>> order(k), factored;
        double factoredC = 0.0;
        uint64_t count = 0, illHere = 0;
        for (uint32_t x = 0; x < width; ++x) {
            const std::size_t row = (static_cast<std::size_t>(y) * width + x) * k;
            table.decode(x, y, idx);
            for (uint32_t j = 0; j < k; ++j) {
                order[j] = {idx[j], j};
            }
            std::sort(order.begin(), order.end());
            const double c = std::max(1e-3, static_cast<double>(mShape) * pts[idx[0]].spacing);
            const bool same =
                c == factoredC && factored.size() == k &&
                std::equal(order.begin(), order.end(), factored.begin(),
                           [](const auto& a, const auto& b) { return a.first == b.first; });
            if (!same) {
                for (uint32_t j = 0; j < k; ++j) {
                    nb[j] = {pts[order[j].first].x, pts[order[j].first].y};
                }
                if (!system.factor(nb, kernel, c)) {
                    ++illHere;
                }
                ++count;
                factored = order;
                factoredC = c;
            }
            const double px = x + 0.5, py = y + 0.5;
            for (uint32_t j = 0; j < k; ++j) {
                const double dx = px - nb[j].x, dy = py - nb[j].y;
                w[j] = rbfKernelOfSquared(kernel, dx * dx + dy * dy, c);
            }
            system.solve(w);
            for (uint32_t j = 0; j < k; ++j) {
                mWeights[row + order[j].second] = static_cast<float>(w[j]);
            }
        }
        factorisations += count;
        ill += illHere;
        step.advance();
    });
    mFactorisations = factorisations;
    mIllConditioned = ill;
    mSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace gt::foveation
