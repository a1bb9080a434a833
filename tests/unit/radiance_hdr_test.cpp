// The strict Radiance reader: it decodes what stb_image writes (run-length encoded and flat)
// exactly as stb_image reads it, and fails with the file's name on every cut or corrupt byte
// where stb_image loops forever or fills in zeros.
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include "core/error.hpp"
#include "scene/environment.hpp"
#include "scene/radiance_hdr.hpp"
#include "support/bad_files.hpp"
#include "support/gpu_test_context.hpp"

namespace gt::scene {
namespace {

using Bytes = std::vector<std::uint8_t>;

// An HDR picture as stb_image_write encodes it: runs for widths 8..32767, flat below.
Bytes encode(int w, int h) {
    std::vector<float> rgb(static_cast<std::size_t>(w) * h * 3);
    for (std::size_t i = 0; i < rgb.size(); ++i) { // smooth runs and noisy literals, 1e-3..1e3
        rgb[i] = (i / 3) % 17 < 9 ? 0.5f : std::exp2(static_cast<float>((i * 7919) % 21) - 10.0f);
    }
    Bytes out;
    stbi_write_hdr_to_func(
        [](void* ctx, void* data, int size) {
            auto* o = static_cast<Bytes*>(ctx);
            const auto* b = static_cast<const std::uint8_t*>(data);
            o->insert(o->end(), b, b + size);
        },
        &out, w, h, 3, rgb.data());
    return out;
}

std::vector<float> stbDecode(const Bytes& b) {
    int w = 0, h = 0, n = 0;
    float* d = stbi_loadf_from_memory(b.data(), static_cast<int>(b.size()), &w, &h, &n, 3);
    EXPECT_NE(d, nullptr) << stbi_failure_reason();
    if (d == nullptr) {
        return {};
    }
    std::vector<float> v(d, d + static_cast<std::size_t>(w) * h * 3);
    stbi_image_free(d);
    return v;
}

std::string error(const Bytes& b) {
    try {
        (void)decodeRadianceHdr(b, "sky.hdr");
    } catch (const LoadError& e) {
        return e.what();
    }
    return {};
}

Bytes text(const std::string& s) {
    return {s.begin(), s.end()};
}

TEST(RadianceHdr, DecodesRunsAndFlatScanlinesAsStbDoes) {
    for (const auto& [w, h] : {std::pair{64, 32}, std::pair{5, 3}}) { // runs, then flat
        const Bytes b = encode(w, h);
        ASSERT_TRUE(isRadianceHdr(b));
        const RgbImage img = decodeRadianceHdr(b, "sky.hdr");
        EXPECT_EQ(img.width, w);
        EXPECT_EQ(img.height, h);
        EXPECT_EQ(img.rgb, stbDecode(b)) << w << "x" << h;
    }
}

TEST(RadianceHdr, EveryCutNamesTheFile) {
    for (const int w : {64, 5}) {
        const Bytes whole = encode(w, 6);
        for (std::size_t size = 0; size < whole.size(); size += 7) {
            const std::string e = error(Bytes(whole.begin(), whole.begin() + size));
            EXPECT_EQ(e.rfind("sky.hdr: ", 0), 0u) << size << " bytes: " << e;
        }
        EXPECT_NE(error(Bytes(whole.begin(), whole.end() - 1)).find("truncated at scanline 5"),
                  std::string::npos);
    }
}

TEST(RadianceHdr, CorruptRunsAndHeadersFail) {
    const std::string head = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n";
    // A zero-length run: stb_image spins on it forever.
    Bytes zeroRun = text(head + "-Y 1 +X 8\n");
    zeroRun.insert(zeroRun.end(), {2, 2, 0, 8, 0});
    EXPECT_NE(error(zeroRun).find("bad run length at scanline 0"), std::string::npos);
    Bytes longRun = text(head + "-Y 1 +X 8\n");
    longRun.insert(longRun.end(), {2, 2, 0, 8, 128 + 9, 7});
    EXPECT_NE(error(longRun).find("bad run length"), std::string::npos);
    Bytes wrongWidth = text(head + "-Y 1 +X 8\n");
    wrongWidth.insert(wrongWidth.end(), {2, 2, 0, 9});
    EXPECT_NE(error(wrongWidth).find("not 8 pixels wide"), std::string::npos);
    EXPECT_NE(error(text("#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n")).find("xyze"),
              std::string::npos);
    EXPECT_NE(error(text(head + "+Y 1 +X 1\n")).find("orientation"), std::string::npos);
    EXPECT_NE(error(text(head + "-Y 0 +X 1\n")).find("out of range"), std::string::npos);
    EXPECT_NE(error(text(head + "-Y 99999999 +X 99999999\n")).find("out of range"),
              std::string::npos);
    EXPECT_NE(error(text(head + "-Y one +X 1\n")).find("bad resolution line"), std::string::npos);
    EXPECT_NE(error(text("P6\n1 1\n255\n")).find("no '#?' signature"), std::string::npos);
}

TEST(RadianceHdr, OldStyleRunsRepeatThePreviousPixel) {
    // Four flat pixels: one literal (0.5, 0.25, 0.125) and (1, 1, 1, 3), three repeats of it.
    Bytes b = text("#?RADIANCE\n\n-Y 1 +X 4\n");
    b.insert(b.end(), {128, 64, 32, 128, 1, 1, 1, 3});
    const RgbImage img = decodeRadianceHdr(b, "sky.hdr");
    ASSERT_EQ(img.rgb.size(), 12u);
    for (int x = 0; x < 4; ++x) {
        EXPECT_EQ(img.rgb[x * 3 + 0], 0.5f) << x;
        EXPECT_EQ(img.rgb[x * 3 + 1], 0.25f) << x;
        EXPECT_EQ(img.rgb[x * 3 + 2], 0.125f) << x;
    }
    Bytes leading = text("#?RADIANCE\n\n-Y 1 +X 4\n");
    leading.insert(leading.end(), {1, 1, 1, 3});
    EXPECT_NE(error(leading).find("bad run length"), std::string::npos);
}

// The shipped skies decode as stb_image decodes them, and a truncated one is refused by
// loadEnvironment rather than read without end.
TEST(RadianceHdr, SharedSkiesMatchStbAndTruncatedOnesFail) {
    const auto content = test::sharedContent();
    if (content.empty()) {
        GTEST_SKIP() << "../shared/content is absent";
    }
    const auto sky = content / "env_spiaggia_di_mondello_1k" / "spiaggia_di_mondello_1k.hdr";
    if (!std::filesystem::exists(sky)) {
        GTEST_SKIP() << sky << " is absent";
    }
    std::ifstream f(sky, std::ios::binary);
    const Bytes b((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    EXPECT_EQ(decodeRadianceHdr(b, sky.string()).rgb, stbDecode(b));
    const auto cut = test::tempDir("radiance") / "half.hdr";
    {
        std::ofstream out(cut, std::ios::binary);
        out.write(reinterpret_cast<const char*>(b.data()),
                  static_cast<std::streamsize>(b.size() / 2));
    }
    try {
        (void)loadEnvironment(cut);
        ADD_FAILURE() << "a truncated sky loaded";
    } catch (const LoadError& e) {
        EXPECT_NE(std::string(e.what()).find("half.hdr: truncated at scanline"), std::string::npos)
            << e.what();
    }
}

} // namespace
} // namespace gt::scene

#include "scene/image_io.hpp"

namespace gt::scene {
namespace {

// A 16384 x 8192 sky never finished loading. Skies past the limit are box-filtered
// down by halves with a warning (here with a small limit, to stay quick).
TEST(Environment, LargerThanTheLimitIsDownsampledWithAWarning) {
    const auto dir = test::tempDir("env_limit");
    std::vector<uint8_t> rgba(64 * 32 * 4);
    for (uint32_t i = 0; i < 64 * 32; ++i) {
        const uint8_t v = (i % 2) ? 255 : 0; // alternating columns: average to grey
        rgba[4 * i] = rgba[4 * i + 1] = rgba[4 * i + 2] = v;
        rgba[4 * i + 3] = 255;
    }
    image::writePngAtomic(dir / "sky.png", 64, 32, rgba);
    std::vector<std::string> warnings;
    const Environment env = loadEnvironment(dir / "sky.png", &warnings, 16);
    EXPECT_EQ(env.width, 16u);
    EXPECT_EQ(env.height, 8u);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("64x32 sky downsampled to 16x8"), std::string::npos) << warnings[0];
    // Box-filtered: every texel is the mean of black and white columns.
    const float grey = env.texels[0].r;
    for (const glm::vec4& t : env.texels) {
        EXPECT_NEAR(t.r, grey, 1e-5f);
    }
    EXPECT_GT(grey, 0.05f);
    EXPECT_LT(grey, 0.95f);
    // Within the limit: as it is, no warning.
    warnings.clear();
    EXPECT_EQ(loadEnvironment(dir / "sky.png", &warnings).width, 64u);
    EXPECT_TRUE(warnings.empty());
}

} // namespace
} // namespace gt::scene

namespace gt::scene {
namespace {

// Found while writing the Radiance fuzz target: a 40-byte file whose header says 16384 x
// 8192 had the reader take and zero 1.5 GiB before finding the data missing; 32768 x 32768 asked
// for 12 GiB. The picture is only allocated once every scanline proved to be there, and past 16384
// x 8192 it is refused. Peak resident memory, not time, tells whether the memory was taken.
TEST(RadianceHdr, AHeaderAloneTakesNoPictureMemory) {
    std::string e;
    EXPECT_LT(test::peakResidentGrowthKiB([&] {
                  e = error(text("#?RADIANCE\n\n-Y 8192 +X 16384\n\x02\x02\x40\x00\x81\x01"));
              }),
              64 * 1024)
        << "KiB taken for a picture that is not there";
    EXPECT_NE(e.find("truncated at scanline 0"), std::string::npos) << e;
    const std::string big = error(text("#?RADIANCE\n\n-Y 32768 +X 32768\n"));
    EXPECT_NE(big.find("32768x32768 pixels, more than the 16384x8192"), std::string::npos) << big;
}

} // namespace
} // namespace gt::scene

#include "support/writerless_fifo.hpp"

namespace gt::scene {
namespace {

// Header numbers were skipped unread: EXPOSURE=nan or COLORCORR=1e999 passed as a sky. None is
// applied (stb_image does not, and cmgen writes EXPOSURE=0), but each must be a finite number.
TEST(RadianceHdr, HeaderNumbersAreFiniteOrTheHeaderIsCorrupt) {
    auto picture = [](const std::string& variable) {
        Bytes b = text("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n" + variable + "\n\n-Y 1 +X 1\n");
        b.insert(b.end(), {128, 64, 32, 129});
        return b;
    };
    EXPECT_NE(error(picture("EXPOSURE=nan")).find("sky.hdr: header line 3: 'EXPOSURE=nan'"),
              std::string::npos)
        << error(picture("EXPOSURE=nan"));
    EXPECT_NE(error(picture("EXPOSURE=1e999")).find("not a finite non-negative number"),
              std::string::npos);
    EXPECT_NE(error(picture("EXPOSURE=-2")).find("EXPOSURE=-2"), std::string::npos);
    EXPECT_NE(error(picture("EXPOSURE=bright")).find("EXPOSURE=bright"), std::string::npos);
    EXPECT_NE(error(picture("COLORCORR=1 1")).find("not 3 finite"), std::string::npos);
    EXPECT_NE(error(picture("PIXASPECT=inf")).find("PIXASPECT=inf"), std::string::npos);
    EXPECT_NE(error(picture("PRIMARIES=0.64 0.33 0.3 0.6 0.15 0.06 nan 0.33")).find("PRIMARIES"),
              std::string::npos);
    // What real writers put there still loads.
    for (const char* ok : {"EXPOSURE=0", "EXPOSURE= 1.5e-2", "GAMMA=1", "COLORCORR=1 1 1\r",
                           "PRIMARIES=0.640 0.330 0.300 0.600 0.150 0.060 0.3127 0.3290"}) {
        EXPECT_EQ(error(picture(ok)), "") << ok;
    }
}

// A FIFO given as a sky or as one cube face blocked the loader forever; /dev/zero grew to 4 GB
// before failing.
TEST(Environment, FifosAndDevicesAreRefusedWithoutReading) {
    const auto dir = test::tempDir("env_kinds");
    auto errorOf = [](const std::filesystem::path& p) {
        return test::thrownMessage<LoadError>([&] { (void)loadEnvironment(p); });
    };
    {
        const test::WriterlessFifo fifo(dir / "sky.hdr");
        const std::string e = errorOf(fifo.path());
        EXPECT_NE(e.find(fifo.path().string() + ": a FIFO"), std::string::npos) << e;
        EXPECT_FALSE(fifo.blockedALoader());
    }
    const auto faces = dir / "cube";
    std::filesystem::create_directories(faces);
    const Bytes face = encode(8, 8);
    for (const char* name : {"px", "nx", "py", "ny", "pz"}) {
        std::ofstream(faces / (std::string(name) + ".hdr"), std::ios::binary)
            .write(reinterpret_cast<const char*>(face.data()),
                   static_cast<std::streamsize>(face.size()));
    }
    {
        const test::WriterlessFifo fifo(faces / "nz.hdr");
        const std::string e = errorOf(faces);
        EXPECT_NE(e.find("nz.hdr: a FIFO"), std::string::npos) << e;
        EXPECT_FALSE(fifo.blockedALoader());
    }
    std::filesystem::create_symlink("/dev/zero", dir / "device.hdr");
    const std::string d = errorOf(dir / "device.hdr");
    EXPECT_NE(d.find("device.hdr: a character device"), std::string::npos) << d;
}

// A PNG sky's size is read from its header and checked before stb_image decodes it (the
// Radiance reader's limit): 16384 x 16384 asked for 3 GiB of floats (stb_image itself refuses
// only what needs more than 1 GiB as bytes).
TEST(Environment, APngSkyPastThePixelLimitIsRefusedFromItsHeader) {
    const auto file = test::tempDir("env_png_limit") / "sky.png";
    Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R'};
    for (const std::uint32_t side : {16384u, 16384u}) {
        for (int shift = 24; shift >= 0; shift -= 8) {
            png.push_back(static_cast<std::uint8_t>(side >> shift));
        }
    }
    png.insert(png.end(), {8, 2, 0, 0, 0, 0, 0, 0, 0}); // 8-bit RGB, then a CRC stb skips
    std::ofstream(file, std::ios::binary)
        .write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
    const std::string e = test::thrownMessage<LoadError>([&] { (void)loadEnvironment(file); });
    EXPECT_NE(e.find("sky.png: 16384x16384 pixels, more than the 16384x8192"), std::string::npos)
        << e;
}

} // namespace
} // namespace gt::scene
