#pragma once
// Reading one recorded eye image (an `images:` folder's frame). The file is read whole through
// the shared input rule (a FIFO or a device is refused, the size is bounded) and decoded from
// memory, after its header has been read here:
//  - the dimensions come from the header before any pixel is decoded, so an image that claims
//    100000 x 100000 is refused by name instead of by an OpenCV assertion naming no file;
//  - a PNG's chunks (lengths, CRCs, the closing IEND), its inflated image data (enough of it,
//    every row filter known) and a JPEG's closing EOI marker are checked, so a truncated or
//    damaged file is one line naming it, not a libpng/libjpeg line on stderr as well.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include <opencv2/core.hpp>

namespace gt::eyetrack {

// The width and height an image's header declares (PNG, JPEG, BMP, PGM/PPM/PBM, TIFF), or
// nothing if the bytes are none of those. Throws FormatError (naming `what`) for a header that
// is cut short or damaged.
[[nodiscard]] std::optional<cv::Size> imageHeaderSize(std::string_view bytes,
                                                      const std::string& what);

// The image at `file`, as stored (IMREAD_UNCHANGED). Throws CaptureError: one line naming the
// file and the reason.
[[nodiscard]] cv::Mat readImageFile(const std::filesystem::path& file);

} // namespace gt::eyetrack
