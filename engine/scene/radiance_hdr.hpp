#pragma once
// Radiance RGBE pictures (.hdr), read strictly. stb_image's reader loops forever on a truncated
// run-length-encoded file and fills what is missing with zeros elsewhere, so a cut-off sky
// either hung the engine or rendered black; this reader names the file and the scanline
// instead. Format: Greg Ward, "Real Pixels" (Graphics Gems II, 1991) and the Radiance file
// format notes: a "#?" header ended by a blank line, a resolution line, then scanlines that
// are flat RGBE pixels, old-style runs (1,1,1,n) or new-style per-channel runs (2,2,hi,lo).
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace gt::scene {

struct RgbImage {
    int width = 0;
    int height = 0;
    std::vector<float> rgb; // linear, row 0 at the top, 3 floats per pixel
};

// True when the bytes start like a Radiance picture ("#?").
[[nodiscard]] bool isRadianceHdr(std::span<const std::uint8_t> bytes) noexcept;

// Decodes a whole picture held in memory; `name` starts every error message.
// Throws gt::LoadError for anything malformed, truncated or unsupported (XYZE, or a
// resolution line other than the usual "-Y H +X W").
[[nodiscard]] RgbImage decodeRadianceHdr(std::span<const std::uint8_t> bytes,
                                         const std::string& name);

} // namespace gt::scene
