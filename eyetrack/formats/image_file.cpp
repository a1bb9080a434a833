#include "formats/image_file.hpp"

#include <array>
#include <cstdlib>
#include <memory>
#include <utility>
#include <vector>

#include <zlib.h>

#include <opencv2/imgcodecs.hpp>

#include "checked_size.hpp"
#include "error.hpp"
#include "input_file.hpp"
#include "limits.hpp"

namespace gt::eyetrack {

namespace {

// Bounds-checked big- and little-endian reads: a short header throws instead of reading past.
class Bytes {
public:
    Bytes(std::string_view bytes, const std::string& what) : mBytes(bytes), mWhat(what) {}
    [[nodiscard]] std::size_t size() const { return mBytes.size(); }
    [[nodiscard]] std::uint32_t be(std::size_t offset, std::size_t n) const {
        need(offset, n);
        std::uint32_t v = 0;
        for (std::size_t i = 0; i < n; ++i) {
            v = (v << 8) | static_cast<unsigned char>(mBytes[offset + i]);
        }
        return v;
    }
    [[nodiscard]] std::uint32_t le(std::size_t offset, std::size_t n) const {
        need(offset, n);
        std::uint32_t v = 0;
        for (std::size_t i = n; i-- > 0;) {
            v = (v << 8) | static_cast<unsigned char>(mBytes[offset + i]);
        }
        return v;
    }
    [[nodiscard]] std::string_view view(std::size_t offset, std::size_t n) const {
        need(offset, n);
        return mBytes.substr(offset, n);
    }
    [[noreturn]] void damaged(const std::string& why) const {
        throw FormatError(mWhat + ": " + why);
    }

private:
    void need(std::size_t offset, std::size_t n) const {
        if (!io::rangeFits(offset, n, mBytes.size())) {
            damaged("truncated (its header is cut short)");
        }
    }
    std::string_view mBytes;
    const std::string& mWhat;
};

// CRC-32 (ISO 3309, as PNG stores it with each chunk).
std::uint32_t crc32(std::string_view data) {
    static const std::array<std::uint32_t, 256> table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t n = 0; n < 256; ++n) {
            std::uint32_t c = n;
            for (int k = 0; k < 8; ++k) {
                c = (c & 1U) ? 0xedb88320U ^ (c >> 1) : c >> 1;
            }
            t[n] = c;
        }
        return t;
    }();
    std::uint32_t c = 0xffffffffU;
    for (const char ch : data) {
        c = table[(c ^ static_cast<unsigned char>(ch)) & 0xffU] ^ (c >> 8);
    }
    return c ^ 0xffffffffU;
}

// The size in the IHDR chunk, which comes first; the rest of the file is checked only once the
// size is known to be within the limits.
cv::Size pngSize(const Bytes& b) {
    if (b.be(8, 4) != 13 || b.view(12, 4) != "IHDR") {
        b.damaged("damaged PNG (no IHDR chunk first)");
    }
    return {static_cast<int>(std::min<std::uint32_t>(b.be(16, 4), 0x7fffffffU)),
            static_cast<int>(std::min<std::uint32_t>(b.be(20, 4), 0x7fffffffU))};
}

// Every chunk whole with its CRC, IEND last: libpng would otherwise print its own "libpng error"
// line for a cut file before OpenCV reports the failure.
void checkPngChunks(const Bytes& b) {
    std::size_t at = 8;
    for (;;) {
        if (at == b.size()) {
            b.damaged("truncated PNG (no IEND chunk)");
        }
        const std::uint32_t length = b.be(at, 4);
        if (length > 0x7fffffffU || !io::rangeFits(at + 8, std::size_t{length} + 4, b.size())) {
            b.damaged("truncated PNG (a chunk runs past the end of the file)");
        }
        const std::string_view typeAndData = b.view(at + 4, 4 + std::size_t{length});
        if (crc32(typeAndData) != b.be(at + 8 + length, 4)) {
            b.damaged("damaged PNG (chunk " + std::string(typeAndData.substr(0, 4)) +
                      " fails its CRC)");
        }
        if (typeAndData.substr(0, 4) == "IEND") {
            break;
        }
        at += 12 + std::size_t{length};
    }
}

// The PNG's image data, inflated and counted against its header before libpng sees it: data that
// does not inflate, too little of it or a row with an unknown filter would each make libpng print
// its own "libpng error" line beside ours. Rows are walked pass by pass (Adam7 when interlaced).
void checkPngImageData(const Bytes& b) {
    const std::uint32_t width = b.be(16, 4), height = b.be(20, 4);
    const std::uint32_t depth = b.be(24, 1), colour = b.be(25, 1), interlace = b.be(28, 1);
    const int channels = colour == 0   ? 1
                         : colour == 2 ? 3
                         : colour == 3 ? 1
                         : colour == 4 ? 2
                         : colour == 6 ? 4
                                       : 0;
    const bool depthFits =
        colour == 0   ? (depth == 1 || depth == 2 || depth == 4 || depth == 8 || depth == 16)
        : colour == 3 ? (depth == 1 || depth == 2 || depth == 4 || depth == 8)
                      : (depth == 8 || depth == 16);
    if (channels == 0 || !depthFits || b.be(26, 1) != 0 || b.be(27, 1) != 0 || interlace > 1) {
        b.damaged("damaged PNG (an invalid IHDR)");
    }
    // Rows of each pass: (bytes per row including its filter byte, row count).
    std::vector<std::pair<std::uint64_t, std::uint64_t>> passes;
    const std::uint64_t bitsPerPixel = static_cast<std::uint64_t>(channels) * depth;
    const auto addPass = [&](std::uint64_t w, std::uint64_t h) {
        if (w > 0 && h > 0) {
            passes.emplace_back(1 + (w * bitsPerPixel + 7) / 8, h);
        }
    };
    if (interlace == 0) {
        addPass(width, height);
    } else {
        constexpr std::array<int, 7> x0{0, 4, 0, 2, 0, 1, 0}, dx{8, 8, 4, 4, 2, 2, 1},
            y0{0, 0, 4, 0, 2, 0, 1}, dy{8, 8, 8, 4, 4, 2, 2};
        for (std::size_t p = 0; p < 7; ++p) {
            addPass((width + dx[p] - 1 - x0[p]) / dx[p], (height + dy[p] - 1 - y0[p]) / dy[p]);
        }
    }
    // The IDAT chunks' data, in order, inflated in pieces; only the filter bytes are looked at.
    z_stream z{};
    if (inflateInit(&z) != Z_OK) {
        b.damaged("cannot check its image data (zlib)");
    }
    const std::unique_ptr<z_stream, int (*)(z_stream*)> guard(&z, inflateEnd);
    std::array<unsigned char, 1 << 16> out{};
    std::size_t pass = 0;
    std::uint64_t row = 0, inRow = 0; // the next byte's row within the pass and offset in it
    int status = Z_OK;
    for (std::size_t at = 8; status != Z_STREAM_END && at < b.size();) {
        const std::uint32_t length = b.be(at, 4);
        const std::string_view type = b.view(at + 4, 4);
        const std::string_view data = b.view(at + 8, length);
        at += 12 + std::size_t{length};
        if (type == "IEND") {
            break;
        }
        if (type != "IDAT") {
            continue;
        }
        z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
        z.avail_in = static_cast<uInt>(data.size());
        while (z.avail_in > 0 && status != Z_STREAM_END) {
            z.next_out = out.data();
            z.avail_out = static_cast<uInt>(out.size());
            const uInt before = z.avail_in;
            status = inflate(&z, Z_NO_FLUSH);
            if ((status != Z_OK && status != Z_STREAM_END && status != Z_BUF_ERROR) ||
                (status == Z_BUF_ERROR && z.avail_in == before && z.next_out == out.data())) {
                b.damaged("damaged PNG (its image data does not inflate)");
            }
            for (const unsigned char* p = out.data(); p < z.next_out; ++p) {
                if (pass == passes.size()) {
                    break; // extra data: libpng ignores it
                }
                if (inRow == 0 && *p > 4) {
                    b.damaged("damaged PNG (a row has an unknown filter)");
                }
                if (++inRow == passes[pass].first) {
                    inRow = 0;
                    if (++row == passes[pass].second) {
                        row = 0;
                        ++pass;
                    }
                }
            }
        }
    }
    if (pass < passes.size()) {
        b.damaged("truncated PNG (not enough image data)");
    }
}

// The frame header (SOFn) before the first scan, and an EOI marker after the last scan: a cut
// JPEG has none, and libjpeg would warn on stderr about the missing data.
cv::Size jpegSize(const Bytes& b, std::string_view bytes) {
    std::size_t at = 2;
    std::optional<cv::Size> size;
    for (;;) {
        if (b.be(at, 1) != 0xff) {
            b.damaged("damaged JPEG (a marker was expected)");
        }
        const std::uint32_t marker = b.be(at + 1, 1);
        if (marker == 0xff) { // fill byte
            ++at;
            continue;
        }
        if (marker == 0xd8 || marker == 0x01 || (marker >= 0xd0 && marker <= 0xd7)) {
            at += 2;
            continue;
        }
        if (marker == 0xd9) {
            b.damaged("damaged JPEG (it ends before its first scan)");
        }
        const std::uint32_t length = b.be(at + 2, 2);
        if (length < 2) {
            b.damaged("damaged JPEG (a segment length below 2)");
        }
        const bool frame =
            marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc;
        if (frame) {
            size = cv::Size(static_cast<int>(b.be(at + 7, 2)), static_cast<int>(b.be(at + 5, 2)));
        }
        if (marker == 0xda) {
            break; // start of scan: entropy-coded data follows
        }
        at += 2 + length;
    }
    if (!size) {
        b.damaged("damaged JPEG (no frame header before its scan)");
    }
    const std::size_t eoi = bytes.rfind("\xff\xd9");
    if (eoi == std::string_view::npos || eoi < at) {
        b.damaged("truncated JPEG (no end marker)");
    }
    return *size;
}

cv::Size bmpSize(const Bytes& b) {
    if (b.le(14, 4) == 12) { // OS/2 core header: 16-bit sizes
        return {static_cast<int>(b.le(18, 2)), static_cast<int>(b.le(20, 2))};
    }
    const auto width = static_cast<std::int32_t>(b.le(18, 4));
    const auto height = static_cast<std::int32_t>(b.le(22, 4)); // negative: stored top-down
    if (width <= 0 || height == 0 || height == INT32_MIN) {
        b.damaged("damaged BMP header");
    }
    return {width, std::abs(height)};
}

// P1..P6: the magic, then width and height as decimal text (with # comments between).
cv::Size pnmSize(const Bytes& b, std::string_view bytes) {
    std::size_t at = 2;
    std::array<long, 2> values{};
    for (long& v : values) {
        for (;;) {
            if (at >= bytes.size()) {
                b.damaged("truncated PNM header");
            }
            if (bytes[at] == '#') {
                const std::size_t end = bytes.find('\n', at);
                if (end == std::string_view::npos) {
                    b.damaged("truncated PNM header");
                }
                at = end + 1;
            } else if (std::isspace(static_cast<unsigned char>(bytes[at]))) {
                ++at;
            } else {
                break;
            }
        }
        std::size_t digits = 0;
        v = 0;
        while (at < bytes.size() && std::isdigit(static_cast<unsigned char>(bytes[at]))) {
            if (++digits > 9) {
                b.damaged("PNM size beyond 10^9");
            }
            v = v * 10 + (bytes[at++] - '0');
        }
        if (digits == 0) {
            b.damaged("damaged PNM header (no width or height)");
        }
    }
    return {static_cast<int>(values[0]), static_cast<int>(values[1])};
}

// The first image's ImageWidth (256) and ImageLength (257) tags.
cv::Size tiffSize(const Bytes& b, bool little) {
    const auto u = [&](std::size_t at, std::size_t n) {
        return little ? b.le(at, n) : b.be(at, n);
    };
    const std::size_t ifd = u(4, 4);
    const std::uint32_t entries = u(ifd, 2);
    int width = 0, height = 0;
    for (std::uint32_t i = 0; i < entries; ++i) {
        const std::size_t e = ifd + 2 + 12 * std::size_t{i};
        const std::uint32_t tag = u(e, 2), type = u(e + 2, 2);
        if (tag != 256 && tag != 257) {
            continue;
        }
        const std::uint32_t v = type == 3 ? u(e + 8, 2) : type == 4 ? u(e + 8, 4) : 0;
        (tag == 256 ? width : height) = static_cast<int>(std::min<std::uint32_t>(v, 0x7fffffffU));
    }
    if (width <= 0 || height <= 0) {
        b.damaged("damaged TIFF (no image width or height)");
    }
    return {width, height};
}

} // namespace

std::optional<cv::Size> imageHeaderSize(std::string_view bytes, const std::string& what) {
    const Bytes b(bytes, what);
    const auto starts = [&](std::string_view magic) {
        return bytes.substr(0, magic.size()) == magic;
    };
    if (starts("\x89PNG\r\n\x1a\n")) {
        return pngSize(b);
    }
    if (starts("\xff\xd8\xff")) {
        return jpegSize(b, bytes);
    }
    if (starts("BM")) {
        return bmpSize(b);
    }
    if (bytes.size() >= 2 && bytes[0] == 'P' && bytes[1] >= '1' && bytes[1] <= '6') {
        return pnmSize(b, bytes);
    }
    if (starts(std::string_view("II*\0", 4))) {
        return tiffSize(b, true);
    }
    if (starts(std::string_view("MM\0*", 4))) {
        return tiffSize(b, false);
    }
    return std::nullopt;
}

cv::Mat readImageFile(const std::filesystem::path& file) {
    const std::string what = "images: " + file.string();
    std::string bytes;
    try {
        bytes = io::readInputFile(file, io::limits::kImageFileBytes);
    } catch (const io::InputError& e) {
        throw CaptureError("images: " + std::string(e.what()));
    }
    std::optional<cv::Size> size;
    try {
        size = imageHeaderSize(bytes, what);
    } catch (const FormatError& e) {
        throw CaptureError(e.what());
    }
    if (!size) {
        throw CaptureError(what + ": not a PNG, JPEG, BMP, PGM/PPM or TIFF image");
    }
    const auto pixels =
        static_cast<std::uint64_t>(size->width) * static_cast<std::uint64_t>(size->height);
    if (size->width <= 0 || size->height <= 0 ||
        size->width > static_cast<int>(io::limits::kEyeImageSide) ||
        size->height > static_cast<int>(io::limits::kEyeImageSide) ||
        pixels > io::limits::kEyeImagePixels) {
        throw CaptureError(
            what + ": " + std::to_string(size->width) + " x " + std::to_string(size->height) +
            " pixels is beyond the limit for an eye "
            "image (" +
            std::to_string(io::limits::kEyeImageSide) + " a side, " +
            std::to_string(io::limits::kEyeImagePixels / (std::uint64_t{1024} * 1024)) + " Mpx)");
    }
    if (bytes.substr(0, 8) == "\x89PNG\r\n\x1a\n") {
        try {
            const Bytes png(bytes, what);
            checkPngChunks(png);
            checkPngImageData(png);
        } catch (const FormatError& e) {
            throw CaptureError(e.what());
        }
    }
    cv::Mat image;
    try {
        const cv::Mat buffer(1, static_cast<int>(bytes.size()), CV_8U, bytes.data());
        image = cv::imdecode(buffer, cv::IMREAD_UNCHANGED);
    } catch (const cv::Exception&) {
        image.release();
    }
    if (image.empty()) {
        throw CaptureError(what + ": cannot be decoded (damaged image data)");
    }
    return image;
}

} // namespace gt::eyetrack
