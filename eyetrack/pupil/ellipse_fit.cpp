#include "pupil/ellipse_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

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

namespace {

// The conic A x'^2 + B x'y' + C y'^2 + D x' + E y' + F = 0 (coefficients in that order) over the
// normalised coordinates x' = (x - mean) s, in image coordinates.
Conic fromNormalised(const std::array<double, 6>& n, cv::Point2d mean, double s) {
    const double A = n[0], B = n[1], C = n[2], D = n[3], E = n[4], F = n[5];
    const double s2 = s * s, mx = mean.x, my = mean.y;
    Conic q;
    q.a = A * s2;
    q.b = B * s2;
    q.c = C * s2;
    q.d = -2.0 * A * s2 * mx - B * s2 * my + D * s;
    q.e = -B * s2 * mx - 2.0 * C * s2 * my + E * s;
    q.f = A * s2 * mx * mx + B * s2 * mx * my + C * s2 * my * my - D * s * mx - E * s * my + F;
    return q;
}

} // namespace

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
    return fromNormalised({n[0], n[1], n[2], n[3], n[4], -1.0}, mean, scale);
}

namespace {

using Mat3 = std::array<std::array<double, 3>, 3>;

// Inverse of a symmetric positive (semi)definite 3x3 matrix by cofactors; nullopt when singular
// relative to its own scale.
std::optional<Mat3> inverse3(const Mat3& m) {
    Mat3 c{};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            const auto& r1 = m[static_cast<std::size_t>((i + 1) % 3)];
            const auto& r2 = m[static_cast<std::size_t>((i + 2) % 3)];
            const auto j1 = static_cast<std::size_t>((j + 1) % 3);
            const auto j2 = static_cast<std::size_t>((j + 2) % 3);
            // Cofactor (i, j), stored transposed: the adjugate.
            c[static_cast<std::size_t>(j)][static_cast<std::size_t>(i)] =
                r1[j1] * r2[j2] - r1[j2] * r2[j1];
        }
    }
    const double det = m[0][0] * c[0][0] + m[0][1] * c[1][0] + m[0][2] * c[2][0];
    double scale = 0.0;
    for (const auto& row : m) {
        for (const double v : row) {
            scale = std::max(scale, std::abs(v));
        }
    }
    if (!(std::abs(det) > 1e-12 * scale * scale * scale)) {
        return std::nullopt;
    }
    for (auto& row : c) {
        for (double& v : row) {
            v /= det;
        }
    }
    return c;
}

// The real roots of x^3 + c2 x^2 + c1 x + c0 (one or three), each polished by Newton's method.
// A fixed array: the refit solves one cubic per call, twice per RANSAC fit.
struct RealRoots {
    std::array<double, 3> values{};
    std::size_t count = 0;
    [[nodiscard]] std::span<const double> all() const { return {values.data(), count}; }
};

RealRoots cubicRoots(double c2, double c1, double c0) {
    // Depressed: x = t - c2 / 3, t^3 + p t + q = 0.
    const double p = c1 - c2 * c2 / 3.0;
    const double q = 2.0 * c2 * c2 * c2 / 27.0 - c2 * c1 / 3.0 + c0;
    const double disc = q * q / 4.0 + p * p * p / 27.0;
    RealRoots roots;
    if (disc > 0.0) {
        const double sq = std::sqrt(disc);
        roots.values[roots.count++] = std::cbrt(-q / 2.0 + sq) + std::cbrt(-q / 2.0 - sq);
    } else if (p == 0.0) {
        roots.values[roots.count++] = 0.0;
    } else {
        const double r = 2.0 * std::sqrt(-p / 3.0);
        const double cosArg = std::clamp(3.0 * q / (p * r), -1.0, 1.0);
        const double phi = std::acos(cosArg) / 3.0;
        for (int k = 0; k < 3; ++k) {
            roots.values[roots.count++] = r * std::cos(phi - 2.0 * std::numbers::pi * k / 3.0);
        }
    }
    for (std::size_t i = 0; i < roots.count; ++i) {
        double x = roots.values[i] - c2 / 3.0;
        for (int it = 0; it < 2; ++it) {
            const double f = ((x + c2) * x + c1) * x + c0;
            const double df = (3.0 * x + 2.0 * c2) * x + c1;
            if (df == 0.0) {
                break;
            }
            x -= f / df;
        }
        roots.values[i] = x;
    }
    return roots;
}

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

// K distinct indices below n, drawn in order (n >= K).
template <std::size_t K>
std::array<std::size_t, K> drawDistinct(std::uint64_t& state, std::size_t n) {
    std::array<std::size_t, K> idx{};
    for (std::size_t k = 0; k < K; ++k) {
        bool fresh = false;
        while (!fresh) {
            idx[k] = static_cast<std::size_t>(splitmix(state) % n);
            fresh = std::find(idx.begin(), idx.begin() + static_cast<std::ptrdiff_t>(k), idx[k]) ==
                    idx.begin() + static_cast<std::ptrdiff_t>(k);
        }
    }
    return idx;
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

// The eigenvector of the reduced scatter matrix r with 4ac - b^2 > 0: the ellipse's quadratic
// part (Fitzgibbon et al.: exactly one); nullopt when none is found.
std::optional<std::array<double, 3>> ellipseEigenvector(const Mat3& r) {
    const double trace = r[0][0] + r[1][1] + r[2][2];
    const double minors = r[0][0] * r[1][1] - r[0][1] * r[1][0] + r[0][0] * r[2][2] -
                          r[0][2] * r[2][0] + r[1][1] * r[2][2] - r[1][2] * r[2][1];
    const double det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                       r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                       r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
    const RealRoots roots = cubicRoots(-trace, minors, -det);
    for (const double lambda : roots.all()) {
        // Eigenvector: the longest cross product of two rows of R - lambda I.
        Mat3 shifted = r;
        for (std::size_t i = 0; i < 3; ++i) {
            shifted[i][i] -= lambda;
        }
        std::array<double, 3> best{};
        double bestNorm = 0.0;
        for (const auto& [i, j] : {std::pair{0, 1}, std::pair{0, 2}, std::pair{1, 2}}) {
            const auto& u = shifted[static_cast<std::size_t>(i)];
            const auto& w = shifted[static_cast<std::size_t>(j)];
            const std::array<double, 3> c{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                                          u[0] * w[1] - u[1] * w[0]};
            const double norm = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
            if (norm > bestNorm) {
                bestNorm = norm;
                best = c;
            }
        }
        if (bestNorm > 0.0 && 4.0 * best[0] * best[2] - best[1] * best[1] > 0.0) {
            return best;
        }
    }
    return std::nullopt;
}

} // namespace

std::optional<Conic> directEllipseFit(std::span<const cv::Point2d> points,
                                      std::span<const int> subset) {
    const std::size_t n = subset.empty() ? points.size() : subset.size();
    if (n < 6) {
        return std::nullopt;
    }
    const auto point = [&](std::size_t k) {
        return subset.empty() ? points[k] : points[static_cast<std::size_t>(subset[k])];
    };
    // Centred and scaled to an RMS distance of sqrt(2): the fourth powers in the scatter matrix
    // stay near 1 whatever the image size.
    cv::Point2d mean(0.0, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
        mean += point(k);
    }
    mean *= 1.0 / static_cast<double>(n);
    double spread = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
        const cv::Point2d d = point(k) - mean;
        spread += d.x * d.x + d.y * d.y;
    }
    if (!(spread > 0.0)) {
        return std::nullopt;
    }
    const double s = std::sqrt(2.0 * static_cast<double>(n) / spread);
    // Halir & Flusser: the design matrix split into its quadratic part D1 = [x^2 xy y^2] and
    // linear part D2 = [x y 1]; S1 = D1'D1, S2 = D1'D2, S3 = D2'D2.
    Mat3 s1{}, s2{}, s3{};
    for (std::size_t k = 0; k < n; ++k) {
        const double x = (point(k).x - mean.x) * s, y = (point(k).y - mean.y) * s;
        const std::array<double, 3> d1{x * x, x * y, y * y}, d2{x, y, 1.0};
        for (std::size_t i = 0; i < 3; ++i) {
            for (std::size_t j = 0; j < 3; ++j) {
                s1[i][j] += d1[i] * d1[j];
                s2[i][j] += d1[i] * d2[j];
                s3[i][j] += d2[i] * d2[j];
            }
        }
    }
    const auto s3inv = inverse3(s3);
    if (!s3inv) {
        return std::nullopt; // the points are collinear
    }
    // The linear part that minimises the residual for given quadratic part a1: a2 = T a1,
    // T = -S3^-1 S2'. The reduced scatter M = S1 + S2 T, premultiplied by the inverse of the
    // constraint's 3x3 block C1 = [[0 0 2] [0 -1 0] [2 0 0]].
    Mat3 t{}, m{};
    for (std::size_t i = 0; i < 3; ++i) {
        for (std::size_t j = 0; j < 3; ++j) {
            for (std::size_t k = 0; k < 3; ++k) {
                t[i][j] -= (*s3inv)[i][k] * s2[j][k];
            }
        }
    }
    for (std::size_t i = 0; i < 3; ++i) {
        for (std::size_t j = 0; j < 3; ++j) {
            m[i][j] = s1[i][j];
            for (std::size_t k = 0; k < 3; ++k) {
                m[i][j] += s2[i][k] * t[k][j];
            }
        }
    }
    const Mat3 r{{{0.5 * m[2][0], 0.5 * m[2][1], 0.5 * m[2][2]},
                  {-m[1][0], -m[1][1], -m[1][2]},
                  {0.5 * m[0][0], 0.5 * m[0][1], 0.5 * m[0][2]}}};
    const std::optional<std::array<double, 3>> a1 = ellipseEigenvector(r);
    if (!a1) {
        return std::nullopt;
    }
    const double A = (*a1)[0], B = (*a1)[1], C = (*a1)[2];
    return fromNormalised({A, B, C, t[0][0] * A + t[0][1] * B + t[0][2] * C,
                           t[1][0] * A + t[1][1] * B + t[1][2] * C,
                           t[2][0] * A + t[2][1] * B + t[2][2] * C},
                          mean, s);
}

int ransacDrawsNeeded(double inlierShare, double confidence, int cap, int sampleSize) {
    // log(1 - p) / log(1 - w^k), clamped to the cap before the cast: a few inliers among many
    // points need billions of draws, more than an int holds.
    const double allInlier =
        std::pow(std::clamp(inlierShare, 0.0, 1.0), static_cast<double>(sampleSize));
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
        const auto idx = drawDistinct<5>(state, n);
        std::array<cv::Point2d, 5> sample;
        for (std::size_t k = 0; k < 5; ++k) {
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
            if (current.size() + (n - i) <= best.size()) {
                break;
            }
            if (inlier(points, i)) {
                current.push_back(static_cast<int>(i));
            }
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
        const auto q = directEllipseFit(points, best);
        const auto ellipse = q ? q->toEllipse() : std::nullopt;
        if (!ellipse || !plausible(*ellipse, params)) {
            return std::nullopt;
        }
        fit.ellipse = *ellipse;
        const InlierTest inlier{*q, outwardSign(*q, fit.ellipse), params, gradients};
        std::vector<int> again;
        for (std::size_t i = 0; i < n; ++i) {
            if (inlier(points, i)) {
                again.push_back(static_cast<int>(i));
            }
        }
        if (again.size() < 6) {
            break;
        }
        best.swap(again);
    }
    fit.inliers = std::move(best);
    fit.draws = it;
    return fit;
}

namespace {

// The frame in which an ellipse of the given shape is a circle, and back.
struct ShapeFrame {
    cv::Point2d major, minor; // unit axes in the image
    double ratio = 1.0;

    [[nodiscard]] cv::Point2d toCircle(cv::Point2d p) const {
        return {p.dot(major), p.dot(minor) / ratio};
    }
    // The image conic of the circle |q - centre| = radius in this frame: with q = (u, v),
    // u = major . p and v = minor . p / ratio, the quadratic part is the same for every circle.
    [[nodiscard]] Conic conicOf(cv::Point2d centre, double radius) const {
        const cv::Point2d v = minor * (1.0 / ratio);
        Conic q;
        q.a = major.x * major.x + v.x * v.x;
        q.b = 2.0 * (major.x * major.y + v.x * v.y);
        q.c = major.y * major.y + v.y * v.y;
        q.d = -2.0 * (centre.x * major.x + centre.y * v.x);
        q.e = -2.0 * (centre.x * major.y + centre.y * v.y);
        q.f = centre.dot(centre) - radius * radius;
        return q;
    }
    [[nodiscard]] cv::RotatedRect toImage(cv::Point2d centre, double radius,
                                          double majorAngleDeg) const {
        const cv::Point2d c = major * centre.x + minor * (centre.y * ratio);
        return {
            cv::Point2f(static_cast<float>(c.x), static_cast<float>(c.y)),
            cv::Size2f(static_cast<float>(2.0 * radius), static_cast<float>(2.0 * radius * ratio)),
            static_cast<float>(majorAngleDeg)};
    }
};

struct Circle {
    cv::Point2d centre;
    double radius = 0.0;
};

std::optional<Circle> circleThrough(cv::Point2d a, cv::Point2d b, cv::Point2d c) {
    const double d = 2.0 * (a.x * (b.y - c.y) + b.x * (c.y - a.y) + c.x * (a.y - b.y));
    if (std::abs(d) < 1e-9) {
        return std::nullopt;
    }
    const double a2 = a.dot(a), b2 = b.dot(b), c2 = c.dot(c);
    const cv::Point2d o((a2 * (b.y - c.y) + b2 * (c.y - a.y) + c2 * (a.y - b.y)) / d,
                        (a2 * (c.x - b.x) + b2 * (a.x - c.x) + c2 * (b.x - a.x)) / d);
    return Circle{o, cv::norm(a - o)};
}

// Kåsa's fit: minimise sum (x^2 + y^2 + D x + E y + F)^2 over the subset, about its mean.
std::optional<Circle> leastSquaresCircle(std::span<const cv::Point2d> q,
                                         std::span<const int> subset) {
    cv::Point2d mean;
    for (const int i : subset) {
        mean += q[static_cast<std::size_t>(i)];
    }
    mean *= 1.0 / static_cast<double>(subset.size());
    Mat3 m{};
    std::array<double, 3> r{};
    for (const int i : subset) {
        const cv::Point2d p = q[static_cast<std::size_t>(i)] - mean;
        const std::array<double, 3> row{p.x, p.y, 1.0};
        const double z = -(p.x * p.x + p.y * p.y);
        for (std::size_t j = 0; j < 3; ++j) {
            for (std::size_t k = 0; k < 3; ++k) {
                m[j][k] += row[j] * row[k];
            }
            r[j] += row[j] * z;
        }
    }
    const auto inv = inverse3(m);
    if (!inv) {
        return std::nullopt;
    }
    std::array<double, 3> x{};
    for (std::size_t j = 0; j < 3; ++j) {
        for (std::size_t k = 0; k < 3; ++k) {
            x[j] += (*inv)[j][k] * r[k];
        }
    }
    const cv::Point2d o(-0.5 * x[0], -0.5 * x[1]);
    const double rr = o.dot(o) - x[2];
    if (!(rr > 0.0)) {
        return std::nullopt;
    }
    return Circle{o + mean, std::sqrt(rr)};
}

} // namespace

std::optional<EllipseFit> fitEllipseOfShapeRansac(std::span<const cv::Point2d> points,
                                                  double axisRatio, double majorAngleDeg,
                                                  const RansacEllipseParams& params,
                                                  std::span<const cv::Point2d> gradients) {
    const std::size_t n = points.size();
    if (n < 6 || !(axisRatio > 0.0 && axisRatio <= 1.0)) {
        return std::nullopt;
    }
    if (!gradients.empty() && gradients.size() != n) {
        gradients = {};
    }
    const double th = majorAngleDeg * std::numbers::pi / 180.0;
    const ShapeFrame frame{{std::cos(th), std::sin(th)}, {-std::sin(th), std::cos(th)}, axisRatio};
    std::vector<cv::Point2d> q(n);
    for (std::size_t i = 0; i < n; ++i) {
        q[i] = frame.toCircle(points[i]);
    }
    RansacEllipseParams shapeParams = params;
    shapeParams.minAxisRatio = 0.0;
    auto sizeIsPlausible = [&](const Circle& c) {
        return std::isfinite(c.radius) && 2.0 * c.radius * axisRatio >= params.minAxis &&
               2.0 * c.radius <= params.maxAxis;
    };
    // The conic's value is negative inside the circle, so its gradient points outwards.
    auto inliersOf = [&](const Circle& circle, std::vector<int>& out, std::size_t beat) {
        out.clear();
        const Conic conic = frame.conicOf(circle.centre, circle.radius);
        const InlierTest inlier{conic, 1.0, shapeParams, gradients};
        for (std::size_t i = 0; i < n; ++i) {
            if (out.size() + (n - i) <= beat) {
                break;
            }
            if (inlier(points, i)) {
                out.push_back(static_cast<int>(i));
            }
        }
    };
    std::uint64_t state = params.seed;
    std::vector<int> best, current;
    const bool adaptive = params.stopConfidence > 0.0 && params.stopConfidence < 1.0;
    int needed = params.iterations;
    int it = 0;
    for (; it < params.iterations && (it < params.minIterations || it < needed); ++it) {
        const auto idx = drawDistinct<3>(state, n);
        const auto circle = circleThrough(q[idx[0]], q[idx[1]], q[idx[2]]);
        if (!circle) {
            continue;
        }
        if (!sizeIsPlausible(*circle)) {
            continue;
        }
        inliersOf(*circle, current, best.size());
        if (current.size() > best.size()) {
            best.swap(current);
            if (adaptive) {
                // Three points a draw: the chance of an all-inlier draw is w^3, not w^5.
                needed =
                    ransacDrawsNeeded(static_cast<double>(best.size()) / static_cast<double>(n),
                                      params.stopConfidence, params.iterations, 3);
            }
        }
    }
    if (best.size() < 6) {
        return std::nullopt;
    }
    EllipseFit fit;
    for (int round = 0; round < 2; ++round) {
        const auto circle = leastSquaresCircle(q, best);
        if (!circle) {
            return std::nullopt;
        }
        const cv::RotatedRect el = frame.toImage(circle->centre, circle->radius, majorAngleDeg);
        if (!plausible(el, shapeParams)) {
            return std::nullopt;
        }
        fit.ellipse = el;
        std::vector<int> again;
        inliersOf(*circle, again, 0);
        if (again.size() < 6) {
            break;
        }
        best.swap(again);
    }
    fit.inliers = std::move(best);
    fit.draws = it;
    return fit;
}

} // namespace gt::eyetrack
