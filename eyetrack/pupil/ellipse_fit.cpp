#include "pupil/ellipse_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <opencv2/imgproc.hpp>

namespace gt::eyetrack {

double Conic::sampsonDistance(cv::Point2d p) const {
    const double gx = 2.0 * a * p.x + b * p.y + d;
    const double gy = b * p.x + 2.0 * c * p.y + e;
    const double g2 = gx * gx + gy * gy;
    return g2 > 0.0 ? std::abs(value(p)) / std::sqrt(g2) : 1e30;
}

std::optional<cv::RotatedRect> Conic::toEllipse() const {
    const double det = 4.0 * a * c - b * b;
    if (det <= 0.0) return std::nullopt;
    const cv::Point2d centre((b * e - 2.0 * c * d) / det, (b * d - 2.0 * a * e) / det);
    // Value at the centre: the conic is (p-c)^T M (p-c) + f0 = 0 with M = [[a, b/2], [b/2, c]].
    const double f0 = value(centre);
    const double tr = a + c;
    const double diff = std::sqrt((a - c) * (a - c) + b * b);
    const double l1 = 0.5 * (tr + diff), l2 = 0.5 * (tr - diff);     // eigenvalues of M
    if (l1 * f0 >= 0.0 || l2 * f0 >= 0.0) return std::nullopt;       // imaginary or degenerate
    const double r1 = std::sqrt(-f0 / l1), r2 = std::sqrt(-f0 / l2); // r1 along l1's eigenvector
    // Eigenvector of l1: angle phi with tan(2 phi) = b / (a - c).
    const double phi = 0.5 * std::atan2(b, a - c);
    const double deg = phi * 180.0 / std::numbers::pi;
    // OpenCV's RotatedRect: width along `angle`, height perpendicular.
    return cv::RotatedRect(cv::Point2f(static_cast<float>(centre.x), static_cast<float>(centre.y)),
                           cv::Size2f(static_cast<float>(2.0 * r1), static_cast<float>(2.0 * r2)),
                           static_cast<float>(deg));
}

Conic Conic::fromEllipse(const cv::RotatedRect& el) {
    const double th = el.angle * std::numbers::pi / 180.0;
    const double ra = 0.5 * el.size.width, rb = 0.5 * el.size.height;
    const double ct = std::cos(th), st = std::sin(th);
    // ((x ct + y st) / ra)^2 + ((-x st + y ct) / rb)^2 = 1, translated to the centre.
    const double A = ct * ct / (ra * ra) + st * st / (rb * rb);
    const double B = 2.0 * ct * st * (1.0 / (ra * ra) - 1.0 / (rb * rb));
    const double C = st * st / (ra * ra) + ct * ct / (rb * rb);
    const double x0 = el.center.x, y0 = el.center.y;
    Conic q;
    q.a = A;
    q.b = B;
    q.c = C;
    q.d = -2.0 * A * x0 - B * y0;
    q.e = -B * x0 - 2.0 * C * y0;
    q.f = A * x0 * x0 + B * x0 * y0 + C * y0 * y0 - 1.0;
    return q;
}

std::optional<Conic> conicThrough(std::span<const cv::Point2d, 5> p) {
    // Centred and scaled coordinates keep the system well conditioned. An ellipse through five
    // points never passes through their centroid (it lies inside), so f != 0 there and the conic
    // can be normalised to f = -1: a 5x5 linear system, solved by Gaussian elimination with
    // partial pivoting (an SVD per RANSAC sample would cost more than the whole detector's budget).
    cv::Point2d mean(0, 0);
    for (const auto& q : p)
        mean += q;
    mean *= 0.2;
    double scale = 0.0;
    for (const auto& q : p)
        scale += cv::norm(q - mean);
    if (scale <= 0.0) return std::nullopt;
    scale = 5.0 / scale;
    double m[5][6];
    for (std::size_t i = 0; i < 5; ++i) {
        const double x = (p[i].x - mean.x) * scale, y = (p[i].y - mean.y) * scale;
        const double row[6] = {x * x, x * y, y * y, x, y, 1.0};
        std::copy(row, row + 6, m[i]);
    }
    for (int col = 0; col < 5; ++col) {
        int pivot = col;
        for (int r = col + 1; r < 5; ++r)
            if (std::abs(m[r][col]) > std::abs(m[pivot][col])) pivot = r;
        if (std::abs(m[pivot][col]) < 1e-10) return std::nullopt;
        if (pivot != col) std::swap(m[pivot], m[col]);
        for (int r = col + 1; r < 5; ++r) {
            const double k = m[r][col] / m[col][col];
            for (int j = col; j < 6; ++j)
                m[r][j] -= k * m[col][j];
        }
    }
    double n[5];
    for (int r = 4; r >= 0; --r) {
        double v = m[r][5];
        for (int j = r + 1; j < 5; ++j)
            v -= m[r][j] * n[j];
        n[r] = v / m[r][r];
    }
    // Conic in normalised coordinates: A x'^2 + B x'y' + C y'^2 + D x' + E y' - 1 = 0.
    // Undo the normalisation x' = (x - mx) s.
    const double A = n[0], B = n[1], C = n[2], D = n[3], E = n[4], F = -1.0;
    const double s = scale, s2 = s * s, mx = mean.x, my = mean.y;
    Conic q;
    q.a = A * s2;
    q.b = B * s2;
    q.c = C * s2;
    q.d = -2.0 * A * s2 * mx - B * s2 * my + D * s;
    q.e = -B * s2 * mx - 2.0 * C * s2 * my + E * s;
    q.f = A * s2 * mx * mx + B * s2 * mx * my + C * s2 * my * my - D * s * mx - E * s * my + F;
    return q;
}

namespace {

bool plausible(const cv::RotatedRect& e, const RansacEllipseParams& p) {
    const double major = std::max(e.size.width, e.size.height);
    const double minor = std::min(e.size.width, e.size.height);
    return std::isfinite(major) && minor >= p.minAxis && major <= p.maxAxis &&
           minor >= p.minAxisRatio * major;
}

// SplitMix64: a tiny deterministic generator so fits are reproducible frame by frame.
std::uint64_t splitmix(std::uint64_t& s) {
    std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

// Inlier test: near the curve and, where the gradient is known, facing the same way as the
// outward normal. Inside an ellipse the conic has the sign of its value at the centre.
struct InlierTest {
    const Conic& q;
    double outward; // +1 when grad Q points outwards, -1 when inwards
    const RansacEllipseParams& params;
    std::span<const cv::Point2d> gradients;

    bool operator()(std::span<const cv::Point2d> points, std::size_t i) const {
        // |Q| / |grad Q| < tol without the square root: this runs for every point in every
        // RANSAC iteration, the detector's innermost loop.
        const cv::Point2d p = points[i];
        const cv::Point2d n = q.gradient(p);
        const double g2 = n.x * n.x + n.y * n.y, v = q.value(p);
        const double tol = params.inlierDistance;
        if (!(v * v < tol * tol * g2)) return false;
        if (gradients.empty()) return true;
        const cv::Point2d g = gradients[i];
        const double along = outward * (n.x * g.x + n.y * g.y);
        return (g.x == 0.0 && g.y == 0.0) || along > params.minNormalCos * std::sqrt(g2);
    }
};

double outwardSign(const Conic& q, const cv::RotatedRect& e) {
    return q.value(cv::Point2d(e.center.x, e.center.y)) < 0.0 ? 1.0 : -1.0;
}

} // namespace

int ransacDrawsNeeded(double inlierShare, double confidence, int cap) {
    // log(1 - p) / log(1 - w^5), clamped to the cap before the cast: a few inliers among many
    // points need billions of draws, more than an int holds.
    const double allInlier = std::pow(std::clamp(inlierShare, 0.0, 1.0), 5.0);
    if (allInlier >= 1.0) return 0;
    if (allInlier <= 0.0) return cap;
    const double draws = std::ceil(std::log(1.0 - confidence) / std::log1p(-allInlier));
    return static_cast<int>(std::clamp(draws, 0.0, static_cast<double>(cap)));
}

std::optional<EllipseFit> fitEllipseRansac(std::span<const cv::Point2d> points,
                                           const RansacEllipseParams& params,
                                           std::span<const cv::Point2d> gradients) {
    const std::size_t n = points.size();
    if (n < 6) return std::nullopt;
    if (!gradients.empty() && gradients.size() != n) gradients = {};
    std::uint64_t state = params.seed;
    std::vector<int> best, current;
    const bool adaptive = params.stopConfidence > 0.0 && params.stopConfidence < 1.0;
    int needed = params.iterations;
    int it = 0;
    for (; it < params.iterations && (it < params.minIterations || it < needed); ++it) {
        std::array<cv::Point2d, 5> sample;
        std::array<std::size_t, 5> idx{};
        for (std::size_t k = 0; k < 5; ++k) {
            bool fresh = false;
            while (!fresh) {
                idx[k] = static_cast<std::size_t>(splitmix(state) % n);
                fresh = std::find(idx.begin(), idx.begin() + static_cast<std::ptrdiff_t>(k),
                                  idx[k]) == idx.begin() + static_cast<std::ptrdiff_t>(k);
            }
            sample[k] = points[idx[k]];
        }
        const auto conic = conicThrough(std::span<const cv::Point2d, 5>(sample));
        if (!conic || !conic->isEllipse()) continue;
        const auto el = conic->toEllipse();
        if (!el || !plausible(*el, params)) continue;
        current.clear();
        const InlierTest inlier{*conic, outwardSign(*conic, *el), params, gradients};
        for (std::size_t i = 0; i < n; ++i) {
            // Stop counting once this draw can no longer beat the best: the usual draw is an
            // outlier's, and only a larger consensus is ever kept.
            if (current.size() + (n - i) <= best.size()) break;
            if (inlier(points, i)) current.push_back(static_cast<int>(i));
        }
        if (current.size() > best.size()) {
            best.swap(current);
            if (adaptive) {
                needed =
                    ransacDrawsNeeded(static_cast<double>(best.size()) / static_cast<double>(n),
                                      params.stopConfidence, params.iterations);
            }
        }
    }
    if (best.size() < 6) return std::nullopt;

    // Least-squares refit on the consensus set, then one more round of inliers against it.
    EllipseFit fit;
    for (int round = 0; round < 2; ++round) {
        std::vector<cv::Point2f> pts;
        pts.reserve(best.size());
        for (int i : best)
            pts.emplace_back(static_cast<float>(points[static_cast<std::size_t>(i)].x),
                             static_cast<float>(points[static_cast<std::size_t>(i)].y));
        fit.ellipse = cv::fitEllipseDirect(pts);
        if (!plausible(fit.ellipse, params)) return std::nullopt;
        const Conic q = Conic::fromEllipse(fit.ellipse);
        const InlierTest inlier{q, outwardSign(q, fit.ellipse), params, gradients};
        std::vector<int> again;
        for (std::size_t i = 0; i < n; ++i)
            if (inlier(points, i)) again.push_back(static_cast<int>(i));
        if (again.size() < 6) break;
        best.swap(again);
    }
    fit.inliers = std::move(best);
    fit.draws = it;
    return fit;
}

} // namespace gt::eyetrack
