// The path-tracing integrator (shaders/common/path.glsl): energy in a white furnace, and
// agreement with an independent brute-force estimate of the same integral on the Cornell box.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "path_test_fixture.hpp"
#include "readback/readback.hpp"
#include "reference/reference.hpp"
#include "render_graph/render_graph.hpp"
#include "scene/builtin_scenes.hpp"
#include "scene/bvh.hpp"
#include "support/gpu_test_context.hpp"
#include "trace/gpu_scene.hpp"
#include "vk/resources.hpp"

namespace gt {
namespace {

using trace::Integrator;

class PathTest : public test::PathFixture {
protected:
    void expectAgreesWithBruteForce(const scene::Scene& s, uint32_t pathRuns, uint32_t bruteRuns);
};

// A sphere of radius 1 at the origin, filling the view of a camera 3 units away, in a sky of
// the same radiance in every direction.
scene::Scene furnace(const scene::Material& m, glm::vec3 sky) {
    scene::Scene s;
    s.name = "furnace";
    scene::SceneBuilder b(s);
    const uint32_t material = b.material(m);
    b.sphere(glm::scale(glm::mat4(1.0f), glm::vec3(2.0f)), material, 96, 192);
    s.sky.horizon = s.sky.zenith = s.sky.ground = sky;
    s.camera.position = {0.0f, 0.0f, 3.0f};
    s.camera.forward = {0.0f, 0.0f, -1.0f};
    s.camera.yfov = glm::radians(40.0f);
    return s;
}

// The pixels inside the sphere's outline: their first ray and their four neighbours' hit it.
// Pixels on the outline mix sky seen past the sphere into their mean.
std::vector<bool> insideSphere(const std::vector<glm::vec4>& image, uint32_t size) {
    std::vector<bool> inside(image.size(), false);
    std::size_t n = 0;
    for (uint32_t y = 1; y + 1 < size; ++y) {
        for (uint32_t x = 1; x + 1 < size; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * size + x;
            inside[i] = std::isfinite(image[i].a) && std::isfinite(image[i - 1].a) &&
                        std::isfinite(image[i + 1].a) && std::isfinite(image[i - size].a) &&
                        std::isfinite(image[i + size].a);
            n += inside[i] ? 1 : 0;
        }
    }
    EXPECT_GT(n, image.size() / 2) << "the sphere should fill most of the view";
    return inside;
}

// The mean radiance over the pixels inside the sphere, relative to the sky's.
glm::dvec3 sphereMeanOverSky(const std::vector<glm::vec4>& image, const std::vector<bool>& inside,
                             glm::vec3 sky) {
    glm::dvec3 sum(0.0);
    std::size_t n = 0;
    for (std::size_t i = 0; i < image.size(); ++i) {
        if (!inside[i]) continue;
        sum += glm::dvec3(image[i]) / glm::dvec3(sky);
        ++n;
    }
    return sum / static_cast<double>(n);
}

// A Lambertian material of albedo 1 (no specular lobe: KHR_materials_specular's factor 0) in a
// uniform sky returns the sky's radiance: every path leaves the convex sphere after one bounce
// and the cosine-weighted sample's weight f cos / pdf is the albedo. 64x64, 16 paths per pixel.
TEST_F(PathTest, WhiteFurnaceLambertianReturnsTheSky) {
    scene::Material white;
    white.baseColor = glm::vec4(1.0f);
    white.specular = 0.0f;
    const glm::vec3 sky(0.8f, 1.0f, 1.25f);
    const scene::Scene s = furnace(white, sky);
    const scene::Bvh bvh(s);
    const trace::GpuScene gpuScene(ctx(), s, bvh);
    const std::vector<glm::vec4> image = render(gpuScene, s, 64, 16, 1, Integrator::Path, 4);
    const glm::dvec3 ratio = sphereMeanOverSky(image, insideSphere(image, 64), sky);
    std::printf("sphere mean / sky: %.5f %.5f %.5f\n", ratio.r, ratio.g, ratio.b);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(ratio[c], 1.0, 0.005) << "channel " << c;
    }
}

// Smith's Lambda for GGX (Heitz 2014, eq. 72), as path.glsl.
double smithLambda(double c, double a2) {
    return 0.5 * (-1.0 + std::sqrt(1.0 + a2 * (1.0 - c * c) / (c * c)));
}

// The directional albedo of the GGX lobe alone with Fresnel 1 (single scattering: D G2 / (4
// n.wo n.wi) with the height-correlated G2) at view cosine mu, by a midpoint rule over the
// half-vector in the variables of GGX's NDF sampling (Walter et al. 2007, eqs. 35-36), where
// D(h) cos(theta_h) dw_h = du dphi / (2 pi) and dw_i = 4 (wo.h) dw_h: the integrand
// G2 (wo.h) / (mu cos(theta_h)) is smooth at any roughness. Independent of the shader's
// sampling.
double ggxAlbedo(double mu, double alpha) {
    constexpr int n = 192;
    const double a2 = alpha * alpha;
    const glm::dvec3 wo(std::sqrt(1.0 - mu * mu), 0.0, mu);
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const double u = (i + 0.5) / n;
        const double tanH = alpha * std::sqrt(u / (1.0 - u));
        const double cosH = 1.0 / std::sqrt(1.0 + tanH * tanH), sinH = tanH * cosH;
        for (int j = 0; j < n; ++j) {
            const double phi = 2.0 * 3.14159265358979 * (j + 0.5) / n;
            const glm::dvec3 h(sinH * std::cos(phi), sinH * std::sin(phi), cosH);
            const double vh = glm::dot(wo, h);
            const glm::dvec3 wi = 2.0 * vh * h - wo;
            if (vh <= 0.0 || wi.z <= 0.0) continue;
            sum += vh / (mu * cosH) / (1.0 + smithLambda(mu, a2) + smithLambda(wi.z, a2));
        }
    }
    return sum / (n * n);
}

// The image mean over the sphere's pixels of furnace() that ggxAlbedo predicts: each pixel
// centre's ray against the ideal sphere, its view cosine looked up in a table of albedos.
double predictedSphereMean(const scene::Scene& s, uint32_t size, const std::vector<bool>& inside,
                           double alpha) {
    constexpr int kTable = 96;
    std::vector<double> table(kTable);
    for (int k = 0; k < kTable; ++k)
        table[k] = ggxAlbedo((k + 0.5) / kTable, alpha);
    const double t = std::tan(0.5 * s.camera.yfov);
    double sum = 0.0;
    int n = 0;
    for (uint32_t y = 0; y < size; ++y) {
        for (uint32_t x = 0; x < size; ++x) {
            const glm::dvec3 d = glm::normalize(glm::dvec3(
                (2.0 * (x + 0.5) / size - 1.0) * t, (1.0 - 2.0 * (y + 0.5) / size) * t, -1.0));
            const glm::dvec3 o(s.camera.position);
            const double b = glm::dot(o, d), c = glm::dot(o, o) - 1.0;
            if (!inside[static_cast<std::size_t>(y) * size + x] || b * b - c <= 0.0) continue;
            const glm::dvec3 p = o + (-b - std::sqrt(b * b - c)) * d;
            const double mu = std::clamp(-glm::dot(p, d), 1e-6, 1.0);
            const double at = std::clamp(mu * kTable - 0.5, 0.0, kTable - 1.0);
            const int k0 = static_cast<int>(at);
            const int k1 = std::min(k0 + 1, kTable - 1);
            sum += table[k0] + (at - k0) * (table[k1] - table[k0]);
            ++n;
        }
    }
    return sum / n;
}

// The microfacet lobe alone (metallic 1, base colour 1: Fresnel is 1) keeps only single
// scattering: light that would leave after bouncing between microfacets is lost, more the
// rougher the surface (no multiple-scattering compensation yet). The path tracer's loss in the
// image mean of the sphere (64x64, 64 paths per pixel) must match the quadrature's within 0.5 %
// of the sky, and the quadrature the loss stated here (docs/path-tracing.md) within 0.5 %.
TEST_F(PathTest, WhiteFurnaceMicrofacetLosesTheMeasuredEnergy) {
    struct Case {
        float roughness;
        double loss; // 1 - sphere mean / sky, as stated
    };
    const Case cases[] = {{0.1f, 0.000}, {0.5f, 0.118}, {1.0f, 0.601}};
    const glm::vec3 sky(1.0f);
    for (const Case& c : cases) {
        scene::Material metal;
        metal.baseColor = glm::vec4(1.0f);
        metal.metallic = 1.0f;
        metal.roughness = c.roughness;
        const scene::Scene s = furnace(metal, sky);
        const scene::Bvh bvh(s);
        const trace::GpuScene gpuScene(ctx(), s, bvh);
        const std::vector<glm::vec4> image = render(gpuScene, s, 64, 64, 2, Integrator::Path, 4);
        const std::vector<bool> inside = insideSphere(image, 64);
        const double measured = 1.0 - sphereMeanOverSky(image, inside, sky).g;
        const double alpha = std::max(static_cast<double>(c.roughness) * c.roughness, 0.002);
        const double predicted = 1.0 - predictedSphereMean(s, 64, inside, alpha);
        std::printf("roughness %.2f: loss %.4f, quadrature %.4f\n", c.roughness, measured,
                    predicted);
        EXPECT_NEAR(measured, predicted, 0.005) << "roughness " << c.roughness;
        EXPECT_NEAR(predicted, c.loss, 0.005) << "roughness " << c.roughness;
    }
}

// glTF's metallic-roughness texture scales the factors (G roughness, B metallic, read linear):
// factors 1 and texels G = 128, B = 255 must lose what roughness 128/255 loses, not what
// roughness 1 does (0.60).
TEST_F(PathTest, MetallicRoughnessTextureScalesTheFactors) {
    scene::Material metal;
    metal.baseColor = glm::vec4(1.0f);
    metal.metallic = 1.0f;
    metal.roughness = 1.0f;
    metal.metallicRoughnessTexture = 0;
    const glm::vec3 sky(1.0f);
    scene::Scene s = furnace(metal, sky);
    scene::Texture t;
    t.width = t.height = 2;
    t.rgba.assign(4, 0xffu | (128u << 8) | (255u << 16) | (255u << 24));
    s.textures.push_back(t);
    const scene::Bvh bvh(s);
    const trace::GpuScene gpuScene(ctx(), s, bvh);
    const std::vector<glm::vec4> image = render(gpuScene, s, 64, 64, 2, Integrator::Path, 4);
    const std::vector<bool> inside = insideSphere(image, 64);
    const double measured = 1.0 - sphereMeanOverSky(image, inside, sky).g;
    const double roughness = 128.0 / 255.0;
    const double predicted = 1.0 - predictedSphereMean(s, 64, inside, roughness * roughness);
    std::printf("textured roughness %.3f: loss %.4f, quadrature %.4f\n", roughness, measured,
                predicted);
    EXPECT_NEAR(measured, predicted, 0.005);
}

// TAA reads the first hit's distance from the radiance's alpha: the path tracer writes the
// same one as the direct integrator for the same camera ray. With independent numbers the pixel
// jitter is the direct integrator's; the Sobol' sequence draws its own (the depth of a ray
// elsewhere in the pixel).
TEST_F(PathTest, FirstHitDepthMatchesTheDirectIntegrator) {
    const scene::Scene s = scene::makeCornell();
    const scene::Bvh bvh(s);
    const trace::GpuScene gpuScene(ctx(), s, bvh);
    const std::vector<glm::vec4> direct = render(gpuScene, s, 24, 2, 3, Integrator::Direct, 1);
    const std::vector<glm::vec4> path =
        render(gpuScene, s, 24, 2, 3, Integrator::Path, 4, trace::SampleSequence::Independent);
    std::size_t finite = 0;
    for (std::size_t i = 0; i < direct.size(); ++i) {
        EXPECT_EQ(direct[i].a, path[i].a) << "pixel " << i;
        finite += std::isfinite(path[i].a) ? 1 : 0;
        EXPECT_TRUE(std::isfinite(path[i].r + path[i].g + path[i].b)) << "pixel " << i;
    }
    EXPECT_GT(finite, direct.size() / 2);
}

// Per 8x8 block and channel, the mean of each image.
std::vector<glm::dvec3> blockMeans(const std::vector<glm::vec4>& image, uint32_t size,
                                   uint32_t block) {
    const uint32_t blocks = size / block;
    std::vector<glm::dvec3> means(static_cast<std::size_t>(blocks) * blocks, glm::dvec3(0.0));
    for (uint32_t y = 0; y < blocks * block; ++y) {
        for (uint32_t x = 0; x < blocks * block; ++x) {
            means[(y / block) * blocks + x / block] +=
                glm::dvec3(image[static_cast<std::size_t>(y) * size + x]) / double(block * block);
        }
    }
    return means;
}

// The path tracer against the brute force on `s` at 32x32 with 4 scattering vertices:
// `pathRuns` runs of 64 paths per pixel against `bruteRuns` of 128 (see
// AgreesWithBruteForceOnCornell).
void PathTest::expectAgreesWithBruteForce(const scene::Scene& s, uint32_t pathRuns,
                                          uint32_t bruteRuns) {
    constexpr uint32_t kSize = 32, kBlock = 8, kBounces = 4, kBruteSpp = 128, kPathSpp = 64;
    const uint32_t kPathRuns = pathRuns, kRuns = bruteRuns;
    const scene::Bvh bvh(s);
    const trace::GpuScene gpuScene(ctx(), s, bvh);
    const auto start = std::chrono::steady_clock::now();
    std::vector<glm::dvec3> path((kSize / kBlock) * (kSize / kBlock), glm::dvec3(0.0));
    std::vector<glm::dvec3> pathSq = path;
    for (uint32_t k = 0; k < kPathRuns; ++k) {
        const std::vector<glm::dvec3> p = blockMeans(
            render(gpuScene, s, kSize, kPathSpp, k, Integrator::Path, kBounces), kSize, kBlock);
        for (std::size_t i = 0; i < p.size(); ++i) {
            path[i] += p[i] / double(kPathRuns);
            pathSq[i] += p[i] * p[i];
        }
    }
    const auto pathDone = std::chrono::steady_clock::now();
    std::vector<glm::dvec3> sum(path.size(), glm::dvec3(0.0)), sumSq = sum;
    for (uint32_t k = 0; k < kRuns; ++k) {
        const std::vector<glm::dvec3> b = blockMeans(
            render(gpuScene, s, kSize, kBruteSpp, 1000 + k, Integrator::BruteForce, kBounces,
                   trace::SampleSequence::Independent), // runs independent: sigma holds
            kSize, kBlock);
        for (std::size_t i = 0; i < b.size(); ++i) {
            sum[i] += b[i];
            sumSq[i] += b[i] * b[i];
        }
    }
    const auto bruteDone = std::chrono::steady_clock::now();
    double worstZ = 0.0;
    glm::dvec3 pathMean(0.0), bruteMean(0.0);
    for (std::size_t i = 0; i < path.size(); ++i) {
        const glm::dvec3 mean = sum[i] / double(kRuns);
        const glm::dvec3 variance = (sumSq[i] - double(kRuns) * mean * mean) / double(kRuns - 1);
        const glm::dvec3 sigma = glm::sqrt(glm::max(variance, 0.0) / double(kRuns));
        for (int c = 0; c < 3; ++c) {
            // A block of sky alone has no spread: there the float sums' rounding is the sigma.
            const double z =
                std::abs(path[i][c] - mean[c]) / std::max(sigma[c], 1e-5 * std::abs(mean[c]));
            worstZ = std::max(worstZ, z);
            const double pathSigma = std::sqrt(
                std::max(pathSq[i][c] / kPathRuns - path[i][c] * path[i][c], 0.0) / kPathRuns);
            EXPECT_LT(z, 3.0) << "block " << i << " channel " << c << ": path " << path[i][c]
                              << " +- " << pathSigma << ", brute force " << mean[c] << " +- "
                              << sigma[c];
        }
        pathMean += path[i] / double(path.size());
        bruteMean += mean / double(path.size());
    }
    const double ms = [](auto a, auto b) {
        return std::chrono::duration<double, std::milli>(b - a).count();
    }(start, pathDone);
    std::printf("worst |z| %.2f; image mean path %.5f %.5f %.5f, brute force %.5f %.5f %.5f; "
                "path %.0f ms, brute force %.0f ms\n",
                worstZ, pathMean.r, pathMean.g, pathMean.b, bruteMean.r, bruteMean.g, bruteMean.b,
                ms, std::chrono::duration<double, std::milli>(bruteDone - pathDone).count());
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(pathMean[c] / bruteMean[c], 1.0, 0.01) << "channel " << c;
    }
}

// The path tracer (next-event estimation, MIS, roulette; clamp off) against the brute-force
// estimate of the same integral (uniform hemisphere sampling, emission only where a path hits
// it; path.glsl's traceBruteForce), on the Cornell box at 32x32, 4 scattering vertices. The
// box is lit by its emissive lamp and the sky through its open front; the spot light that
// stands in for the lamp is skipped by both. Its mirror block is made glossy (roughness 0.4),
// which uniform sampling can estimate. The brute force runs 64 times at 128 paths per pixel
// with different seeds; its sigma per block is their spread / sqrt(64). The path tracer
// (64 runs of 64 paths per pixel) must lie within 3 sigma of the brute force's mean in every
// 8x8 block and channel, and within 1 % of its image mean. Runs stay short because llvmpipe
// ends every loop of an invocation once all its loops together have run 65535 iterations
// (gallivm's loop limiter): a single run of 4096 paths per pixel came out 5x too dark.
TEST_F(PathTest, AgreesWithBruteForceOnCornell) {
    scene::Scene s = scene::makeCornell();
    for (scene::Material& m : s.materials) {
        if (m.name == "mirror") m.roughness = 0.4f;
    }
    expectAgreesWithBruteForce(s, 64, 64);
}

// The same under an environment map with a small bright patch (a sun) over a floor, a diffuse
// and a glossy block: the path tracer samples the map by its luminance (marginal and
// conditional CDFs) and weighs that against the BSDF samples that find it; the brute force
// finds it only by uniform directions.
TEST_F(PathTest, AgreesWithBruteForceUnderAnEnvironmentMap) {
    scene::Scene s;
    s.name = "environment";
    scene::SceneBuilder b(s);
    scene::Material floor, red, glossy;
    floor.baseColor = glm::vec4(0.7f, 0.7f, 0.7f, 1.0f);
    red.baseColor = glm::vec4(0.7f, 0.15f, 0.1f, 1.0f);
    glossy.baseColor = glm::vec4(0.9f, 0.8f, 0.5f, 1.0f);
    glossy.metallic = 1.0f;
    glossy.roughness = 0.4f;
    b.quad({-2, 0, 2}, {4, 0, 0}, {0, 0, -4}, b.material(floor));
    b.box(glm::scale(glm::translate(glm::mat4(1.0f), {-0.6f, 0.5f, 0.0f}),
                     glm::vec3(0.8f, 1.0f, 0.8f)),
          b.material(red));
    b.box(glm::scale(glm::translate(glm::mat4(1.0f), {0.6f, 0.35f, 0.3f}), glm::vec3(0.7f)),
          b.material(glossy));
    s.environment.width = 64;
    s.environment.height = 32;
    s.environment.texels.assign(64 * 32, glm::vec4(0.25f, 0.3f, 0.4f, 1.0f));
    for (uint32_t y = 7; y < 10; ++y) {
        for (uint32_t x = 40; x < 44; ++x)
            s.environment.texels[y * 64 + x] = glm::vec4(60.0f, 55.0f, 45.0f, 1.0f);
    }
    s.camera = scene::lookAt({0.0f, 2.2f, 3.5f}, {0.0f, 0.3f, 0.0f}, glm::radians(50.0f));
    expectAgreesWithBruteForce(s, 64, 64);
}

// The root-mean-square difference of two radiance images (rgb).
double rmse(const std::vector<glm::vec4>& a, const std::vector<glm::vec4>& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const glm::dvec3 d = glm::dvec3(a[i]) - glm::dvec3(b[i]);
        sum += glm::dot(d, d);
    }
    return std::sqrt(sum / (3.0 * static_cast<double>(a.size())));
}

// The Sobol' sequence (sequence_shared.h) stratifies a pixel's paths within a frame and across
// the frames it pools: on the Cornell box at 32x32, 4 vertices, both 16 paths in one frame and
// 16 frames of 1 path each (frame seeds 0..15, averaged) come closer to a 512-path estimate
// than independent random numbers do. Both sequences are unbiased (AgreesWithBruteForce runs
// Sobol'), so the difference is variance.
TEST_F(PathTest, SobolSequenceConvergesFasterInAFrameAndOverFrames) {
    const scene::Scene s = scene::makeCornell();
    const scene::Bvh bvh(s);
    const trace::GpuScene gpuScene(ctx(), s, bvh);
    constexpr uint32_t kSize = 32, kBounces = 4, kPaths = 16;
    using trace::SampleSequence;
    const std::vector<glm::vec4> truth =
        render(gpuScene, s, kSize, 512, 4096, Integrator::Path, kBounces, SampleSequence::Sobol);
    for (const bool overFrames : {false, true}) {
        double error[2] = {0.0, 0.0};
        for (const SampleSequence seq : {SampleSequence::Sobol, SampleSequence::Independent}) {
            std::vector<glm::vec4> image;
            if (!overFrames) {
                image = render(gpuScene, s, kSize, kPaths, 0, Integrator::Path, kBounces, seq);
            } else {
                image.assign(static_cast<std::size_t>(kSize) * kSize, glm::vec4(0.0f));
                for (uint32_t frame = 0; frame < kPaths; ++frame) {
                    const std::vector<glm::vec4> f =
                        render(gpuScene, s, kSize, 1, frame, Integrator::Path, kBounces, seq);
                    for (std::size_t i = 0; i < f.size(); ++i)
                        image[i] += f[i] / float(kPaths);
                }
            }
            error[seq == SampleSequence::Sobol ? 0 : 1] = rmse(image, truth);
        }
        std::printf("%s: RMSE sobol %.5f, independent %.5f (ratio %.3f)\n",
                    overFrames ? "16 frames x 1 path" : "1 frame x 16 paths", error[0], error[1],
                    error[0] / error[1]);
        EXPECT_LT(error[0], 0.9 * error[1]) << (overFrames ? "over frames" : "in a frame");
    }
}

} // namespace
} // namespace gt
