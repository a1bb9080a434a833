#pragma once
// The k x k system of radial basis function interpolation (thesis, eq. 8):
// A_ab = phi(|x_a - x_b|) over k points, with the Gaussian (eq. 9) or multiquadric (eq. 10)
// kernel. It is factored once (LU with partial pivoting, in double: multiquadric matrices with
// c near the point spacing are badly conditioned) and then solved for any number of right-hand
// sides: the unit vectors for RbfInverse, phi(|x - x_j|) at a pixel for RbfPixelWeights.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace gt::foveation {

enum class RbfKernelType : uint32_t { Multiquadric = 0, Gaussian = 1 };

// phi(r) with shape c (a length): sqrt(r^2 + c^2) (eq. 10) or exp(-(r/c)^2) (eq. 9).
[[nodiscard]] double rbfKernel(RbfKernelType kernel, double r, double c) noexcept;
// The same from r^2, which both kernels need (one square root fewer per entry).
[[nodiscard]] double rbfKernelOfSquared(RbfKernelType kernel, double r2, double c) noexcept;

class RbfSystem {
public:
    explicit RbfSystem(uint32_t k);

    // Builds A over `points` (k of them) and factors it. Returns false when a pivot fell below
    // 1e-12 and was clamped (the system is then regularised, not exact).
    bool factor(std::span<const glm::vec2> points, RbfKernelType kernel, double c);
    // Solves A x = rhs in place with the last factorisation.
    void solve(std::span<double> rhs) const;

private:
    uint32_t mK;
    std::vector<double> mLu;       // k x k, row-major: L below the diagonal (unit), U on and above
    std::vector<uint32_t> mPivots; // row swapped with row i at step i
};

} // namespace gt::foveation
