#pragma once
// Precomputed RBF systems (thesis, eq. 8). The neighbourhood of every point q — q and its
// k-1 nearest neighbours — depends on the point set alone, so the inverse of its k x k kernel
// matrix phi(|x_a - x_b|) is computed once per (k, kernel, c). Each frame then only needs
// lambda = inverse * f (k^2 multiply-adds per point) instead of a k x k solve per pixel.
// Neighbours that the frame did not sample (beyond the screen margin) take q's colour, so the
// stored inverse never depends on the gaze.
#include <cstdint>
#include <vector>

#include "foveation/neighbour_index.hpp"
#include "foveation/point_set.hpp"
#include "foveation/rbf_system.hpp"

namespace gt::foveation {

struct RbfInverse {
    uint32_t k = 0;
    RbfKernelType kernel = RbfKernelType::Multiquadric;
    float shape = 1.0f;         // c in units of the point's spacing p
    std::vector<float> inverse; // per point, k x k row-major
    double seconds = 0.0;
    uint32_t illConditioned = 0; // systems whose pivot fell below 1e-12 (regularised)
};

[[nodiscard]] RbfInverse buildRbfInverse(const PointSet& set, const NeighbourIndex& index,
                                         uint32_t k, RbfKernelType kernel, float shape);

} // namespace gt::foveation
