#include "foveation/rbf_system.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace gt::foveation {

double rbfKernel(RbfKernelType kernel, double r, double c) noexcept {
    return rbfKernelOfSquared(kernel, r * r, c);
}

double rbfKernelOfSquared(RbfKernelType kernel, double r2, double c) noexcept {
    if (kernel == RbfKernelType::Gaussian) {
        return std::exp(-r2 / (c * c));
    }
    return std::sqrt(r2 + c * c);
}

RbfSystem::RbfSystem(uint32_t k) : mK(k), mLu(static_cast<std::size_t>(k) * k), mPivots(k) {}

bool RbfSystem::factor(std::span<const glm::vec2> points, RbfKernelType kernel, double c) {
    const uint32_t k = mK;
    for (uint32_t r = 0; r < k; ++r) {
        mLu[r * k + r] = rbfKernelOfSquared(kernel, 0.0, c) + 1e-9; // a whisker of regularisation
        for (uint32_t s = r + 1; s < k; ++s) {
            const double dx = static_cast<double>(points[r].x) - points[s].x;
            const double dy = static_cast<double>(points[r].y) - points[s].y;
            mLu[r * k + s] = mLu[s * k + r] = rbfKernelOfSquared(kernel, dx * dx + dy * dy, c);
        }
    }
    bool wellConditioned = true;
    double* const a = mLu.data();
    for (uint32_t col = 0; col < k; ++col) {
        uint32_t piv = col;
        double best = std::abs(a[col * k + col]);
        for (uint32_t r = col + 1; r < k; ++r) {
            const double v = std::abs(a[r * k + col]);
            if (v > best) {
                best = v;
                piv = r;
            }
        }
        mPivots[col] = piv;
        double* const pivotRow = a + static_cast<std::size_t>(col) * k;
        if (piv != col) {
            std::swap_ranges(pivotRow, pivotRow + k, a + static_cast<std::size_t>(piv) * k);
        }
        double& d = pivotRow[col];
        if (std::abs(d) < 1e-12) {
            wellConditioned = false;
            d = d < 0.0 ? -1e-12 : 1e-12;
        }
        const double inv = 1.0 / d;
        for (uint32_t r = col + 1; r < k; ++r) {
            double* const row = a + static_cast<std::size_t>(r) * k;
            const double f = row[col] * inv;
            row[col] = f;
            for (uint32_t s = col + 1; s < k; ++s) {
                row[s] -= f * pivotRow[s];
            }
        }
    }
    return wellConditioned;
}

void RbfSystem::solve(std::span<double> rhs) const {
    const uint32_t k = mK;
    for (uint32_t i = 0; i < k; ++i) {
        std::swap(rhs[i], rhs[mPivots[i]]);
        for (uint32_t j = 0; j < i; ++j) {
            rhs[i] -= mLu[i * k + j] * rhs[j];
        }
    }
    for (uint32_t i = k; i-- > 0;) {
        for (uint32_t j = i + 1; j < k; ++j) {
            rhs[i] -= mLu[i * k + j] * rhs[j];
        }
        rhs[i] /= mLu[i * k + i];
    }
}

} // namespace gt::foveation
