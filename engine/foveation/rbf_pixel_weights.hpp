#pragma once
// RBF interpolation solved per pixel, as the thesis does (thesis, eqs. 7-8), but once instead
// of every frame. For a canvas pixel x with its k nearest points x_1..x_k (a PixelKnnTable row)
// the interpolant is s(x) = sum_j lambda_j phi(|x - x_j|) with A lambda = f (eq. 8), so
// s(x) = phi(x)^T A^-1 f = sum_j w_j f_j with w = A^-1 phi(x) (A is symmetric). The weights w
// depend on the point set's geometry alone — the set only shifts with the gaze, by whole
// pixels — so a frame's RBF costs one weighted sum of k samples per pixel, as Modified Shepard
// does. Stored k floats per canvas pixel: 2W x 2H x k x 4 B, 590 MB for fove at k = 20.
#include <cstdint>
#include <vector>

#include "foveation/pixel_knn_table.hpp"
#include "foveation/point_set.hpp"
#include "foveation/rbf_system.hpp"

namespace gt::foveation {

class RbfPixelWeights {
public:
    // `shape` is c in units of the spacing p of the pixel's nearest point (as RbfInverse).
    RbfPixelWeights(const PointSet& set, const PixelKnnTable& table, RbfKernelType kernel,
                    float shape);

    [[nodiscard]] uint32_t k() const noexcept { return mK; }
    [[nodiscard]] RbfKernelType kernel() const noexcept { return mKernel; }
    [[nodiscard]] float shape() const noexcept { return mShape; }
    // Row-major over the canvas, k weights per pixel in the table's neighbour order.
    [[nodiscard]] const std::vector<float>& weights() const noexcept { return mWeights; }
    [[nodiscard]] std::size_t bytes() const noexcept { return mWeights.size() * sizeof(float); }
    [[nodiscard]] double buildSeconds() const noexcept { return mSeconds; }
    // Systems factored: neighbouring pixels with the same k points share one factorisation.
    [[nodiscard]] uint64_t factorisations() const noexcept { return mFactorisations; }
    // Systems whose pivot fell below 1e-12 and were regularised.
    [[nodiscard]] uint64_t illConditioned() const noexcept { return mIllConditioned; }

private:
    uint32_t mK;
    RbfKernelType mKernel;
    float mShape;
    std::vector<float> mWeights;
    double mSeconds = 0.0;
    uint64_t mFactorisations = 0, mIllConditioned = 0;
};

} // namespace gt::foveation
