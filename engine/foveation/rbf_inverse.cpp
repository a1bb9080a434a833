#include "foveation/rbf_inverse.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "core/error.hpp"

namespace gt::foveation {

double rbfKernel(RbfKernelType kernel, double r, double c) noexcept {
    if (kernel == RbfKernelType::Gaussian) {
        const double x = r / c;
        return std::exp(-x * x);
    }
    return std::sqrt(r * r + c * c);
}

RbfInverse buildRbfInverse(const PointSet& set, const NeighbourIndex& index, uint32_t k,
                           RbfKernelType kernel, float shape) {
    if (k == 0 || k > index.k() + 1)
        throw ArgumentError("RBF k must be 1.." + std::to_string(index.k() + 1));
    if (!(shape > 0.0f)) throw ArgumentError("RBF shape c must be positive");
    const auto start = std::chrono::steady_clock::now();
    const auto& pts = set.points();
    RbfInverse out;
    out.k = k;
    out.kernel = kernel;
    out.shape = shape;
    out.inverse.resize(pts.size() * k * k);
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::vector<uint32_t> ill(threads, 0);
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t) {
        pool.emplace_back([&, t] {
            std::vector<double> a(k * k), inv(k * k);
            std::vector<uint32_t> nb(k);
            for (std::size_t q = t; q < pts.size(); q += threads) {
                nb[0] = static_cast<uint32_t>(q);
                for (uint32_t j = 1; j < k; ++j)
                    nb[j] = index.neighbours()[q * index.k() + j - 1];
                const double c = std::max(1e-3, static_cast<double>(shape) * pts[q].spacing);
                for (uint32_t r = 0; r < k; ++r) {
                    for (uint32_t s = 0; s < k; ++s) {
                        const double dx = pts[nb[r]].x - pts[nb[s]].x,
                                     dy = pts[nb[r]].y - pts[nb[s]].y;
                        a[r * k + s] = rbfKernel(kernel, std::sqrt(dx * dx + dy * dy), c);
                        inv[r * k + s] = r == s ? 1.0 : 0.0;
                    }
                    a[r * k + r] += 1e-9; // a whisker of regularisation
                }
                // Gauss-Jordan with partial pivoting.
                for (uint32_t col = 0; col < k; ++col) {
                    uint32_t piv = col;
                    for (uint32_t r = col + 1; r < k; ++r) {
                        if (std::abs(a[r * k + col]) > std::abs(a[piv * k + col])) piv = r;
                    }
                    if (piv != col) {
                        for (uint32_t s = 0; s < k; ++s) {
                            std::swap(a[col * k + s], a[piv * k + s]);
                            std::swap(inv[col * k + s], inv[piv * k + s]);
                        }
                    }
                    double d = a[col * k + col];
                    if (std::abs(d) < 1e-12) {
                        ++ill[t];
                        d = d < 0 ? -1e-12 : 1e-12;
                    }
                    for (uint32_t s = 0; s < k; ++s) {
                        a[col * k + s] /= d;
                        inv[col * k + s] /= d;
                    }
                    for (uint32_t r = 0; r < k; ++r) {
                        if (r == col) continue;
                        const double f = a[r * k + col];
                        if (f == 0.0) continue;
                        for (uint32_t s = 0; s < k; ++s) {
                            a[r * k + s] -= f * a[col * k + s];
                            inv[r * k + s] -= f * inv[col * k + s];
                        }
                    }
                }
                float* dst = &out.inverse[q * k * k];
                for (uint32_t i = 0; i < k * k; ++i)
                    dst[i] = static_cast<float>(inv[i]);
            }
        });
    }
    for (auto& th : pool)
        th.join();
    for (uint32_t n : ill)
        out.illConditioned += n;
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

} // namespace gt::foveation
