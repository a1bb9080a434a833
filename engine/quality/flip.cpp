#include "flip.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>

#include <glm/glm.hpp>

#include "filters.hpp"

namespace gt::quality {

namespace {

constexpr double kPi = std::numbers::pi;
// FLIP's exponents and error redistribution (Andersson et al. 2020, section 4).
constexpr double kQc = 0.7;   // colour error exponent
constexpr double kQf = 0.5;   // feature error exponent
constexpr double kPc = 0.4;   // share of the largest colour error...
constexpr double kPt = 0.95;  // ...that maps to this error
constexpr double kGw = 0.082; // peak-to-trough width of the edge detector, degrees
// The D65 white of linear sRGB (1, 1, 1) in XYZ.
const glm::vec3 kWhite(0.950428545f, 1.0f, 1.088900371f);

// Contrast-sensitivity filters per opponent channel (Y, Cx, Cz), each a1 sqrt(pi/b1)
// exp(-pi^2 x^2 / b1) + a2 sqrt(pi/b2) exp(-pi^2 x^2 / b2) with x in degrees.
struct Csf {
    double a1, b1, a2, b2;
};
constexpr std::array<Csf, 3> kCsf{{{1.0, 0.0047, 0.0, 1e-5},    // achromatic
                                   {1.0, 0.0053, 0.0, 1e-5},    // red-green
                                   {34.1, 0.04, 13.5, 0.025}}}; // blue-yellow
constexpr double kCsfMaxB = 0.04;

float srgbToLinear(float c) {
    return c > 0.04045f ? std::pow((c + 0.055f) / 1.055f, 2.4f) : c / 12.92f;
}
glm::vec3 linearToXyz(glm::vec3 c) {
    // sRGB primaries, D65 (exact rational coefficients).
    return {(10135552.0f * c.r + 8788810.0f * c.g + 4435075.0f * c.b) / 24577794.0f,
            (2613072.0f * c.r + 8788810.0f * c.g + 887015.0f * c.b) / 12288897.0f,
            (1425312.0f * c.r + 8788810.0f * c.g + 70074185.0f * c.b) / 73733382.0f};
}
glm::vec3 xyzToLinear(glm::vec3 c) {
    return {3.241003275f * c.x - 1.537398934f * c.y - 0.498615861f * c.z,
            -0.969224334f * c.x + 1.875930071f * c.y + 0.041554224f * c.z,
            0.055639423f * c.x - 0.204011202f * c.y + 1.057148933f * c.z};
}
glm::vec3 xyzToYcxcz(glm::vec3 xyz) {
    const glm::vec3 n = xyz / kWhite;
    return {116.0f * n.y - 16.0f, 500.0f * (n.x - n.y), 200.0f * (n.y - n.z)};
}
glm::vec3 ycxczToXyz(glm::vec3 c) {
    const float y = (c.x + 16.0f) / 116.0f;
    return glm::vec3(y + c.y / 500.0f, y, y - c.z / 200.0f) * kWhite;
}
// CIELAB with the Hunt adjustment: colourfulness grows with lightness (a, b scaled by L / 100).
glm::vec3 huntLab(glm::vec3 linear) {
    const glm::vec3 n = linearToXyz(linear) / kWhite;
    constexpr float delta = 6.0f / 29.0f;
    auto f = [&](float t) {
        return t > delta * delta * delta ? std::cbrt(t) : t / (3.0f * delta * delta) + 4.0f / 29.0f;
    };
    const float fx = f(n.x), fy = f(n.y), fz = f(n.z);
    const float l = 116.0f * fy - 16.0f;
    return {l, 0.01f * l * 500.0f * (fx - fy), 0.01f * l * 200.0f * (fy - fz)};
}
float hyab(glm::vec3 a, glm::vec3 b) {
    const glm::vec3 d = a - b;
    return std::abs(d.x) + std::sqrt(d.y * d.y + d.z * d.z);
}

// The opponent channels of an sRGB picture, one map each.
std::array<ScalarMap, 3> toYcxcz(const RgbaImage& img) {
    std::array<ScalarMap, 3> out;
    for (ScalarMap& m : out) {
        m.resize(img.count());
    }
    std::array<float, 256> lut{};
    for (int i = 0; i < 256; ++i) {
        lut[static_cast<std::size_t>(i)] = srgbToLinear(static_cast<float>(i) / 255.0f);
    }
    for (std::size_t p = 0; p < img.count(); ++p) {
        const glm::vec3 c =
            xyzToYcxcz(linearToXyz({lut[img.at(p, 0)], lut[img.at(p, 1)], lut[img.at(p, 2)]}));
        out[0][p] = c.x;
        out[1][p] = c.y;
        out[2][p] = c.z;
    }
    return out;
}

// Each opponent channel filtered by its contrast-sensitivity function, back in linear RGB
// clamped to [0, 1], then Hunt-adjusted CIELAB.
std::vector<glm::vec3> filteredLab(const std::array<ScalarMap, 3>& ycxcz, uint32_t w, uint32_t h,
                                   double ppd) {
    const int radius =
        static_cast<int>(std::ceil(3.0 * std::sqrt(kCsfMaxB / (2.0 * kPi * kPi)) * ppd));
    std::array<ScalarMap, 3> filtered;
    for (std::size_t c = 0; c < 3; ++c) {
        const Csf& s = kCsf[c];
        // Each Gaussian term is separable: g(x) g(y) with g(x) = exp(-pi^2 (x / ppd)^2 / b).
        // The 2-D filter is normalised to sum 1 over its square support.
        std::array<Kernel, 2> g;
        std::array<double, 2> weight{s.a1 * std::sqrt(kPi / s.b1), s.a2 * std::sqrt(kPi / s.b2)};
        const std::array<double, 2> b{s.b1, s.b2};
        double total = 0.0;
        for (std::size_t t = 0; t < 2; ++t) {
            g[t].resize(2 * static_cast<std::size_t>(radius) + 1);
            double sum = 0.0;
            for (std::size_t j = 0; j < g[t].size(); ++j) {
                const double x = (static_cast<double>(j) - radius) / ppd;
                const double v = std::exp(-kPi * kPi * x * x / b[t]);
                g[t][j] = static_cast<float>(v);
                sum += v;
            }
            total += weight[t] * sum * sum;
        }
        filtered[c].assign(ycxcz[c].size(), 0.0f);
        for (std::size_t t = 0; t < 2; ++t) {
            if (weight[t] == 0.0) {
                continue;
            }
            const ScalarMap part = convolveSeparable(ycxcz[c], w, h, g[t], g[t]);
            const auto k = static_cast<float>(weight[t] / total);
            for (std::size_t p = 0; p < part.size(); ++p) {
                filtered[c][p] += k * part[p];
            }
        }
    }
    std::vector<glm::vec3> lab(ycxcz[0].size());
    for (std::size_t p = 0; p < lab.size(); ++p) {
        const glm::vec3 rgb = glm::clamp(
            xyzToLinear(ycxczToXyz({filtered[0][p], filtered[1][p], filtered[2][p]})), 0.0f, 1.0f);
        lab[p] = huntLab(rgb);
    }
    return lab;
}

// Edge (first derivative) or point (second derivative) detector of a Gaussian along x, with
// its positive weights summing to 1 and its negative ones to -1; the Gaussian across.
struct FeatureKernels {
    Kernel edge, point, across;
};
FeatureKernels featureKernels(double ppd) {
    const double sd = 0.5 * kGw * ppd;
    const int radius = static_cast<int>(std::ceil(3.0 * sd));
    FeatureKernels k;
    k.across = gaussianKernel(sd, radius);
    auto normalised = [&](auto shape) {
        Kernel v(2 * static_cast<std::size_t>(radius) + 1);
        double pos = 0.0, neg = 0.0;
        for (std::size_t j = 0; j < v.size(); ++j) {
            const double x = static_cast<double>(j) - radius;
            const double val = shape(x) * std::exp(-x * x / (2.0 * sd * sd));
            v[j] = static_cast<float>(val);
            (val > 0.0 ? pos : neg) += val;
        }
        for (float& x : v) {
            x = static_cast<float>(x > 0.0f ? x / pos : (x < 0.0f ? x / -neg : 0.0));
        }
        return v;
    };
    k.edge = normalised([](double x) { return -x; });
    k.point = normalised([sd](double x) { return x * x / (sd * sd) - 1.0; });
    return k;
}

// |edge response| and |point response| of the normalised luminance.
std::array<ScalarMap, 2> features(const ScalarMap& y, uint32_t w, uint32_t h,
                                  const FeatureKernels& k) {
    const ScalarMap ex = convolveSeparable(y, w, h, k.edge, k.across);
    const ScalarMap ey = convolveSeparable(y, w, h, k.across, k.edge);
    const ScalarMap px = convolveSeparable(y, w, h, k.point, k.across);
    const ScalarMap py = convolveSeparable(y, w, h, k.across, k.point);
    std::array<ScalarMap, 2> out{ScalarMap(y.size()), ScalarMap(y.size())};
    for (std::size_t p = 0; p < y.size(); ++p) {
        out[0][p] = std::hypot(ex[p], ey[p]);
        out[1][p] = std::hypot(px[p], py[p]);
    }
    return out;
}

} // namespace

double pixelsPerDegree(double widthPx, double viewingDistance) {
    return widthPx * viewingDistance * kPi / 180.0;
}

ScalarMap flipErrorMap(const RgbaImage& reference, const RgbaImage& test, double ppd) {
    if (reference.width != test.width || reference.height != test.height ||
        reference.pixels.size() != reference.count() * 4 ||
        test.pixels.size() != test.count() * 4) {
        throw std::invalid_argument("FLIP: the images differ in size");
    }
    if (!(ppd > 0.0) || !std::isfinite(ppd)) {
        throw std::invalid_argument("FLIP: pixels per degree must be positive");
    }
    const uint32_t w = reference.width, h = reference.height;
    const auto refOpp = toYcxcz(reference);
    const auto testOpp = toYcxcz(test);

    // Colour: HyAB in Hunt-adjusted CIELAB after the contrast-sensitivity filters.
    const std::vector<glm::vec3> refLab = filteredLab(refOpp, w, h, ppd);
    const std::vector<glm::vec3> testLab = filteredLab(testOpp, w, h, ppd);
    const double cmax =
        std::pow(hyab(huntLab({0.0f, 1.0f, 0.0f}), huntLab({0.0f, 0.0f, 1.0f})), kQc);
    const double pcCmax = kPc * cmax;

    // Features on the luminance relative to white, (Y + 16) / 116 in [0, 1].
    const FeatureKernels k = featureKernels(ppd);
    auto luminance = [](const std::array<ScalarMap, 3>& opp) {
        ScalarMap y(opp[0].size());
        for (std::size_t p = 0; p < y.size(); ++p) {
            y[p] = (opp[0][p] + 16.0f) / 116.0f;
        }
        return y;
    };
    const auto refF = features(luminance(refOpp), w, h, k);
    const auto testF = features(luminance(testOpp), w, h, k);

    ScalarMap out(reference.count());
    for (std::size_t p = 0; p < out.size(); ++p) {
        const double e = std::pow(static_cast<double>(hyab(refLab[p], testLab[p])), kQc);
        const double colour =
            e < pcCmax ? kPt / pcCmax * e : kPt + (e - pcCmax) / (cmax - pcCmax) * (1.0 - kPt);
        const double df =
            std::max(std::abs(refF[0][p] - testF[0][p]), std::abs(refF[1][p] - testF[1][p]));
        const double feature = std::pow(df / std::numbers::sqrt2, kQf);
        out[p] = static_cast<float>(std::pow(std::min(colour, 1.0), 1.0 - feature));
    }
    return out;
}

} // namespace gt::quality
