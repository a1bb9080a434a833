#include "scene/radiance_hdr.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "checked_size.hpp"
#include "core/error.hpp"
#include "limits.hpp"

namespace gt::scene {

namespace {

// Beyond this a picture is more likely a corrupt header than an environment map. The pixel
// count is bounded by io::limits::kSkyPixels: the environment loader halves anything wider
// than it keeps; a larger picture is refused rather than decoded.
constexpr int kMaxSide = 1 << 15;

class Reader {
public:
    Reader(std::span<const std::uint8_t> bytes, const std::string& name)
        : mBytes(bytes), mName(name) {}

    [[noreturn]] void fail(const std::string& what) const { throw LoadError(mName + ": " + what); }

    [[nodiscard]] std::size_t at() const noexcept { return mAt; }
    void seek(std::size_t at) noexcept { mAt = at; }

    // One header line without its '\n'; the header must end before the data does.
    std::string_view line() {
        const std::size_t start = mAt;
        while (mAt < mBytes.size() && mBytes[mAt] != '\n') {
            ++mAt;
        }
        if (mAt == mBytes.size()) {
            fail("truncated header");
        }
        const std::string_view l(reinterpret_cast<const char*>(mBytes.data()) + start, mAt - start);
        ++mAt;
        return l;
    }

    std::uint8_t byte(int scanline) {
        if (mAt == mBytes.size()) {
            fail("truncated at scanline " + std::to_string(scanline));
        }
        return mBytes[mAt++];
    }

private:
    std::span<const std::uint8_t> mBytes;
    const std::string& mName;
    std::size_t mAt = 0;
};

void readResolution(Reader& in, std::string_view l, int& width, int& height) {
    // Only the orientation every common writer uses: top row first, left to right.
    char ySign = 0, xSign = 0, yAxis = 0, xAxis = 0;
    long h = 0, w = 0;
    char extra = 0;
    const std::string s(l);
    if (std::sscanf(s.c_str(), " %c%c %ld %c%c %ld %c", &ySign, &yAxis, &h, &xSign, &xAxis, &w,
                    &extra) != 6) {
        in.fail("bad resolution line '" + s + "'");
    }
    if (ySign != '-' || yAxis != 'Y' || xSign != '+' || xAxis != 'X') {
        in.fail("unsupported orientation '" + s + "' (only -Y H +X W)");
    }
    if (w < 1 || h < 1 || w > kMaxSide || h > kMaxSide) {
        in.fail("resolution " + std::to_string(w) + "x" + std::to_string(h) + " out of range");
    }
    const auto pixels =
        io::checkedMul(static_cast<std::uint64_t>(w), static_cast<std::uint64_t>(h));
    if (!pixels || *pixels > io::limits::kSkyPixels) {
        in.fail(std::to_string(w) + "x" + std::to_string(h) +
                " pixels, more than the 16384x8192 gazetrace reads");
    }
    width = static_cast<int>(w);
    height = static_cast<int>(h);
}

// Header variables that carry numbers (Radiance file format notes). gazetrace applies none of
// them (stb_image does not either, and cmgen writes EXPOSURE=0), but one that is not a finite
// number (nan, 1e999, text) marks a corrupt header, not a picture to guess at.
struct NumericVariable {
    std::string_view name;
    int count;
    bool nonNegative;
};
constexpr std::array<NumericVariable, 5> kNumericVariables = {{{"EXPOSURE=", 1, true},
                                                               {"GAMMA=", 1, true},
                                                               {"PIXASPECT=", 1, true},
                                                               {"COLORCORR=", 3, true},
                                                               {"PRIMARIES=", 8, false}}};

// The numbers after "NAME=": how many parse as finite numbers (and non-negative ones where
// asked), or -1 at the first that does not.
int countNumbers(const std::string& values, bool nonNegative) {
    const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
    const char* p = values.c_str();
    int n = 0;
    while (true) {
        while (blank(*p)) {
            ++p;
        }
        if (*p == '\0') {
            return n;
        }
        char* end = nullptr;
        const double x = std::strtod(p, &end);
        if (end == p || !(*end == '\0' || blank(*end)) || !std::isfinite(x) ||
            (nonNegative && x < 0.0)) {
            return -1;
        }
        p = end;
        ++n;
    }
}

void checkHeaderNumbers(const Reader& in, std::string_view l, int lineNo) {
    for (const NumericVariable& v : kNumericVariables) {
        if (!l.starts_with(v.name)) {
            continue;
        }
        if (countNumbers(std::string(l.substr(v.name.size())), v.nonNegative) != v.count) {
            const std::string shown(l.substr(0, 80));
            in.fail("header line " + std::to_string(lineNo) + ": '" + shown + "' is not " +
                    (v.count == 1 ? std::string("a") : std::to_string(v.count)) + " finite" +
                    (v.nonNegative ? " non-negative" : "") +
                    (v.count == 1 ? " number" : " numbers"));
        }
    }
}

// New-style scanline after its (2, 2, hi, lo) marker: each of R, G, B, E run-length encoded
// on its own. A run byte > 128 repeats the next byte (byte - 128) times; otherwise that many
// literal bytes follow. Zero-length and overlong runs are corrupt (stb loops on the former).
void decodeChannels(Reader& in, int y, std::vector<std::uint8_t>& rgbe) {
    const int width = static_cast<int>(rgbe.size() / 4);
    for (int c = 0; c < 4; ++c) {
        int x = 0;
        while (x < width) {
            int count = in.byte(y);
            const bool run = count > 128;
            if (run) {
                count -= 128;
            }
            if (count == 0 || count > width - x) {
                in.fail("bad run length at scanline " + std::to_string(y));
            }
            if (run) {
                const std::uint8_t v = in.byte(y);
                for (int i = 0; i < count; ++i) {
                    rgbe[static_cast<std::size_t>(x++) * 4 + c] = v;
                }
            } else {
                for (int i = 0; i < count; ++i) {
                    rgbe[static_cast<std::size_t>(x++) * 4 + c] = in.byte(y);
                }
            }
        }
    }
}

// Flat pixels, where (1, 1, 1, n) repeats the previous pixel n << shift times and consecutive
// repeats shift by 8 more bits each. `first` holds the four bytes already read.
void decodeFlat(Reader& in, int y, std::vector<std::uint8_t>& rgbe, const std::uint8_t first[4]) {
    const int width = static_cast<int>(rgbe.size() / 4);
    std::uint8_t p[4] = {first[0], first[1], first[2], first[3]};
    int x = 0, shift = 0;
    while (true) {
        if (p[0] == 1 && p[1] == 1 && p[2] == 1) {
            const long count = static_cast<long>(p[3]) << shift;
            if (x == 0 || count > width - x) {
                in.fail("bad run length at scanline " + std::to_string(y));
            }
            for (long i = 0; i < count; ++i, ++x) {
                for (int c = 0; c < 4; ++c) {
                    rgbe[static_cast<std::size_t>(x) * 4 + c] =
                        rgbe[static_cast<std::size_t>(x - 1) * 4 + c];
                }
            }
            shift += 8;
            if (shift > 16) {
                in.fail("bad run length at scanline " + std::to_string(y));
            }
        } else {
            for (int c = 0; c < 4; ++c) {
                rgbe[static_cast<std::size_t>(x) * 4 + c] = p[c];
            }
            ++x;
            shift = 0;
        }
        if (x == width) {
            return;
        }
        for (std::uint8_t& b : p) {
            b = in.byte(y);
        }
    }
}

// One scanline into `rgbe` (width x 4 bytes), in whichever encoding it starts with.
void decodeScanline(Reader& in, int y, std::vector<std::uint8_t>& rgbe) {
    const int width = static_cast<int>(rgbe.size() / 4);
    std::uint8_t head[4];
    for (std::uint8_t& b : head) {
        b = in.byte(y);
    }
    const bool newRle =
        width >= 8 && width < 0x8000 && head[0] == 2 && head[1] == 2 && (head[2] & 0x80) == 0;
    if (newRle) {
        if ((head[2] << 8 | head[3]) != width) {
            in.fail("scanline " + std::to_string(y) + " is not " + std::to_string(width) +
                    " pixels wide");
        }
        decodeChannels(in, y, rgbe);
    } else {
        decodeFlat(in, y, rgbe, head);
    }
}

} // namespace

bool isRadianceHdr(std::span<const std::uint8_t> bytes) noexcept {
    return bytes.size() >= 2 && bytes[0] == '#' && bytes[1] == '?';
}

RgbImage decodeRadianceHdr(std::span<const std::uint8_t> bytes, const std::string& name) {
    Reader in(bytes, name);
    if (!isRadianceHdr(bytes)) {
        in.fail("not a Radiance picture (no '#?' signature)");
    }
    (void)in.line(); // "#?RADIANCE", "#?RGBE" or another program's name
    for (int lineNo = 2;; ++lineNo) {
        const std::string_view l = in.line();
        if (l.empty()) {
            break;
        }
        if (l.starts_with("FORMAT=") && l != "FORMAT=32-bit_rle_rgbe") {
            in.fail("unsupported " + std::string(l) + " (only 32-bit_rle_rgbe)");
        }
        checkHeaderNumbers(in, l, lineNo);
    }
    RgbImage img;
    readResolution(in, in.line(), img.width, img.height);
    // Two passes: the first only checks that every scanline is there and well formed, so a
    // header that promises a large picture in a few bytes (12 GB asked for by a
    // 30-byte file) fails before the picture's memory is taken; the second decodes.
    const std::size_t scanlines = in.at();
    std::vector<std::uint8_t> rgbe(static_cast<std::size_t>(img.width) * 4);
    for (int y = 0; y < img.height; ++y) {
        decodeScanline(in, y, rgbe);
    }
    in.seek(scanlines);
    img.rgb.resize(static_cast<std::size_t>(img.width) * img.height * 3);
    for (int y = 0; y < img.height; ++y) {
        decodeScanline(in, y, rgbe);
        float* out = &img.rgb[static_cast<std::size_t>(y) * img.width * 3];
        for (int x = 0; x < img.width; ++x) {
            const std::uint8_t* p = &rgbe[static_cast<std::size_t>(x) * 4];
            // value = mantissa * 2^(E - 128 - 8), as stb_image decodes it (Radiance adds 0.5
            // to the mantissa; keeping stb's form keeps every rendered sky as it was).
            const float f = p[3] == 0 ? 0.0f : std::ldexp(1.0f, static_cast<int>(p[3]) - 136);
            for (int c = 0; c < 3; ++c) {
                out[x * 3 + c] = static_cast<float>(p[c]) * f;
            }
        }
    }
    return img;
}

} // namespace gt::scene
