// engine/quality: LDR-FLIP's documented properties and simple pairs with known answers, PSNR,
// SSIM, the bleeding mask, eccentricity bands and the upscaling filters.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "quality/eccentricity_bands.hpp"
#include "quality/flip.hpp"
#include "quality/image_metrics.hpp"
#include "quality/resample.hpp"

namespace q = gt::quality;

namespace {

q::RgbaImage solid(uint32_t w, uint32_t h, uint8_t r, uint8_t g, uint8_t b) {
    q::RgbaImage img{w, h, std::vector<uint8_t>(static_cast<std::size_t>(w) * h * 4)};
    for (std::size_t p = 0; p < img.count(); ++p) {
        img.pixels[4 * p] = r;
        img.pixels[4 * p + 1] = g;
        img.pixels[4 * p + 2] = b;
        img.pixels[4 * p + 3] = 255;
    }
    return img;
}

void set(q::RgbaImage& img, uint32_t x, uint32_t y, uint8_t v) {
    const std::size_t p = static_cast<std::size_t>(y) * img.width + x;
    img.pixels[4 * p] = img.pixels[4 * p + 1] = img.pixels[4 * p + 2] = v;
}

double mean(const q::ScalarMap& m) {
    return std::accumulate(m.begin(), m.end(), 0.0) / static_cast<double>(m.size());
}

constexpr double kPpd = 67.0; // FLIP's default observer: a 0.7 m wide 4K monitor at 0.7 m

} // namespace

TEST(Flip, IdenticalImagesGiveZero) {
    q::RgbaImage a = solid(48, 40, 90, 140, 30);
    for (uint32_t i = 0; i < 40; ++i) {
        set(a, i, i, 250); // a diagonal line: features that must cancel too
    }
    const q::ScalarMap m = q::flipErrorMap(a, a, kPpd);
    EXPECT_EQ(*std::max_element(m.begin(), m.end()), 0.0f);
}

TEST(Flip, BlackAgainstWhiteIsAtTheTopOfTheScale) {
    // HyAB(black, white) = 100 is below the largest colour distance (green against blue, which
    // maps to 1): 100^0.7 lies past pc * cmax, so it maps into (pt, 1] = (0.95, 1].
    const q::ScalarMap bw =
        q::flipErrorMap(solid(32, 32, 0, 0, 0), solid(32, 32, 255, 255, 255), kPpd);
    EXPECT_GT(mean(bw), 0.95);
    EXPECT_LT(mean(bw), 0.98);
    const q::ScalarMap gb =
        q::flipErrorMap(solid(32, 32, 0, 255, 0), solid(32, 32, 0, 0, 255), kPpd);
    EXPECT_NEAR(mean(gb), 1.0, 1e-4);
    // A white image against a black one with a white dot, seen from close (10 px/deg, where
    // the colour filters barely blur): the dot's pixel matches, but the point it makes is a
    // feature the white image lacks, which pushes the error beside it towards 1.
    q::RgbaImage dots = solid(32, 32, 0, 0, 0);
    set(dots, 16, 16, 255);
    const q::ScalarMap d = q::flipErrorMap(solid(32, 32, 255, 255, 255), dots, 10.0);
    EXPECT_NEAR(d[16 * 32 + 17], 1.0, 0.02);
}

TEST(Flip, ErrorGrowsWithContrast) {
    const q::RgbaImage ref = solid(24, 24, 100, 100, 100);
    double last = 0.0;
    for (const int d : {2, 8, 32, 120}) {
        const auto v = static_cast<uint8_t>(100 + d);
        const double e = mean(q::flipErrorMap(ref, solid(24, 24, v, v, v), kPpd));
        EXPECT_GT(e, last) << "difference " << d;
        last = e;
    }
}

TEST(Flip, ErrorFallsWithViewingDistance) {
    // One-pixel stripes against their mean grey: seen from afar (more pixels per degree) the
    // contrast-sensitivity filters average the stripes away.
    // The grey is the stripes' mean in linear light (sRGB 200 and 56 -> 0.578 and 0.040 ->
    // 0.309 -> sRGB 151). Measured away from the borders, which replicate the edge stripe.
    const q::RgbaImage grey = solid(160, 160, 151, 151, 151);
    q::RgbaImage stripes = grey;
    for (uint32_t y = 0; y < 160; ++y) {
        for (uint32_t x = 0; x < 160; ++x) {
            set(stripes, x, y, x % 2 ? 200 : 56);
        }
    }
    auto centre = [](const q::ScalarMap& m) {
        double sum = 0.0;
        for (uint32_t y = 48; y < 112; ++y) {
            for (uint32_t x = 48; x < 112; ++x) {
                sum += m[static_cast<std::size_t>(y) * 160 + x];
            }
        }
        return sum / (64.0 * 64.0);
    };
    double last = 2.0;
    for (const double ppd : {5.0, 15.0, 40.0, 120.0}) {
        const double e = centre(q::flipErrorMap(grey, stripes, ppd));
        EXPECT_LT(e, last) << ppd << " pixels per degree";
        last = e;
    }
    EXPECT_THROW((void)q::flipErrorMap(grey, solid(8, 8, 0, 0, 0), kPpd), std::invalid_argument);
    EXPECT_THROW((void)q::flipErrorMap(grey, grey, 0.0), std::invalid_argument);
}

TEST(Flip, PixelsPerDegreeFollowsTheDisplay) {
    // FLIP's default: 3840 pixels 0.7 m wide seen from 0.7 m (v = 1) -> 67.02 px/deg.
    EXPECT_NEAR(q::pixelsPerDegree(3840.0, 1.0), 67.02, 0.01);
}

TEST(ImageMetrics, PsnrAndSsimOfKnownPairs) {
    const q::RgbaImage a = solid(32, 32, 100, 100, 100), b = solid(32, 32, 116, 116, 116);
    EXPECT_FLOAT_EQ(mean(q::squaredErrorMap(a, b)), 256.0f);
    EXPECT_FLOAT_EQ(mean(q::absoluteErrorMap(a, b)), 16.0f);
    EXPECT_NEAR(q::psnrDb(256.0), 24.0484, 1e-3); // 10 log10(255^2 / 256)
    EXPECT_EQ(q::psnrDb(0.0), 99.0);
    q::RgbaImage tex = a;
    for (uint32_t y = 0; y < 32; ++y) {
        for (uint32_t x = 0; x < 32; ++x) {
            set(tex, x, y, static_cast<uint8_t>(((x / 4 + y / 4) % 2) ? 180 : 40));
        }
    }
    EXPECT_NEAR(mean(q::ssimMap(tex, tex)), 1.0, 1e-6);
    EXPECT_LT(mean(q::ssimMap(tex, a)), 0.2); // the texture gone
    q::RgbaImage faded = tex;
    for (std::size_t p = 0; p < faded.count(); ++p) {
        for (int c = 0; c < 3; ++c) {
            faded.pixels[4 * p + c] = static_cast<uint8_t>(110 + (tex.at(p, c) - 110) / 2);
        }
    }
    const double s = mean(q::ssimMap(tex, faded));
    EXPECT_GT(s, 0.6);
    EXPECT_LT(s, 0.99);
}

TEST(ImageMetrics, DarkNearBrightMask) {
    q::RgbaImage img = solid(40, 20, 10, 10, 10);
    set(img, 5, 10, 255);
    for (uint32_t y = 0; y < 20; ++y) {
        set(img, 30, y, 100); // mid-grey: neither dark nor bright
    }
    const auto m = q::darkNearBrightMask(img);
    auto at = [&](uint32_t x, uint32_t y) { return m[static_cast<std::size_t>(y) * 40 + x]; };
    EXPECT_EQ(at(5, 10), 0);  // the bright pixel itself
    EXPECT_EQ(at(15, 10), 1); // 10 px away
    EXPECT_EQ(at(16, 10), 0); // 11 px away
    EXPECT_EQ(at(11, 18), 1); // dx 6, dy 8: distance 10
    EXPECT_EQ(at(12, 18), 0); // distance 10.6
    EXPECT_EQ(at(30, 10), 0); // not dark
}

TEST(EccentricityBands, FromTheDisplayGeometry) {
    gt::foveation::DisplayProfile d{"test", 1000, 500, 1.0};
    // e = atan(dist / (N v)): 5 deg at 87.5 px, 10 deg at 176.3 px, 20 deg at 364 px.
    const auto bands = q::bandMap(d, 1000, 500, {500.0f, 250.0f});
    auto at = [&](int x) { return bands[250 * 1000 + static_cast<std::size_t>(x)]; };
    EXPECT_EQ(at(500), 0);
    EXPECT_EQ(at(500 + 87), 0);
    EXPECT_EQ(at(500 + 88), 1);
    EXPECT_EQ(at(500 + 177), 2);
    EXPECT_EQ(at(500 + 365), 3);
    const auto n = q::pixelsPerBand(bands);
    EXPECT_EQ(n[0] + n[1] + n[2] + n[3], 500000u);
    q::ScalarMap ones(bands.size(), 1.0f);
    EXPECT_EQ(q::meanPerBand(ones, bands)[2], 1.0);
    EXPECT_DOUBLE_EQ(q::acuityFalloff(0.0), 1.0);
    EXPECT_NEAR(q::acuityFalloff(2.3), 0.5, 1e-12); // e2: half resolution
}

TEST(Resample, BilinearAndCatmullRom) {
    q::RgbaImage ramp{8, 1, std::vector<uint8_t>(8 * 4)};
    for (uint32_t x = 0; x < 8; ++x) {
        set(ramp, x, 0, static_cast<uint8_t>(20 * x + 10));
    }
    for (const auto f : {q::Upscale::Bilinear, q::Upscale::CatmullRom}) {
        const q::RgbaImage up = q::upscale(ramp, 16, 2, f);
        // Both reproduce a linear ramp away from the clamped ends: 20 per source pixel,
        // 10 per destination pixel, centres aligned.
        for (uint32_t x = 4; x < 12; ++x) {
            EXPECT_NEAR(up.at(x, 0), 5.0 + 10.0 * x - 2.5 + 2.5, 1.0) << x;
            EXPECT_EQ(up.at(x, 0), up.at(16 + x, 0)); // the rows are alike
        }
        const q::RgbaImage flat = q::upscale(solid(5, 3, 77, 77, 77), 13, 7, f);
        for (std::size_t p = 0; p < flat.count(); ++p) {
            ASSERT_EQ(flat.at(p, 1), 77);
        }
    }
    // Catmull-Rom is sharper: across a step it overshoots where bilinear does not.
    q::RgbaImage step = solid(8, 1, 50, 50, 50);
    for (uint32_t x = 4; x < 8; ++x) {
        set(step, x, 0, 200);
    }
    const q::RgbaImage bl = q::upscale(step, 32, 1, q::Upscale::Bilinear);
    const q::RgbaImage cr = q::upscale(step, 32, 1, q::Upscale::CatmullRom);
    uint8_t maxBl = 0, maxCr = 0;
    for (uint32_t x = 0; x < 32; ++x) {
        maxBl = std::max(maxBl, bl.at(x, 0));
        maxCr = std::max(maxCr, cr.at(x, 0));
    }
    EXPECT_EQ(maxBl, 200);
    EXPECT_GT(maxCr, 200);
}
