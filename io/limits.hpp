#pragma once
// Every size and count limit gazetrace applies to what it reads, in one place; the limits table
// in docs/reliability.md lists them with the reason for each. A limit is refused with one line
// naming the file or the value and the limit.
#include <cstdint>

namespace gt::io::limits {

inline constexpr std::uint64_t kKiB = 1024;
inline constexpr std::uint64_t kMiB = 1024 * kKiB;
inline constexpr std::uint64_t kGiB = 1024 * kMiB;

// Text tables (gaze traces, camera paths, truth CSVs, target lists) and small JSON documents
// (calibrations): a day of 1 kHz gaze samples is ~3 GB, far beyond any run; an hour is ~150 MB.
inline constexpr std::uint64_t kTextTableBytes = 256 * kMiB;
inline constexpr std::uint64_t kJsonDocumentBytes = 64 * kMiB;
// A .gltf document, and each external buffer it names or a whole GLB (it carries its buffer).
inline constexpr std::uint64_t kGltfDocumentBytes = 256 * kMiB;
inline constexpr std::uint64_t kGltfBufferBytes = 2 * kGiB;
// All of a glTF file's base-colour textures as decoded RGBA: 400 of 2048 x 2048 took 7.5 GB;
// Sponza's are ~0.3 GB. GltfLoadOptions::maxTextureBytes, GAZETRACE_MAX_TEXTURE_BYTES.
inline constexpr std::uint64_t kGltfTextureBytes = 2 * kGiB;
// One encoded image file (PNG, JPEG, Radiance .hdr, a cube face, an eval reference).
inline constexpr std::uint64_t kImageFileBytes = 512 * kMiB;
// One recorded eye image (an `images:` folder's frame), by the size its header declares, checked
// before decoding: an eye camera's frame is well under 4096 a side; OpenCV asserts (naming no
// file) beyond 2^20 a side or 2^30 pixels, and a 16-bit RGBA frame of 64 Mpx decodes to 512 MiB.
inline constexpr std::uint64_t kEyeImageSide = 1 << 16;
inline constexpr std::uint64_t kEyeImagePixels = 64 * kMiB;
// A cached point set or k-NN table.
inline constexpr std::uint64_t kCacheFileBytes = 4 * kGiB;
// A recorded eye video.
inline constexpr std::uint64_t kVideoFileBytes = 64 * kGiB;

// Pixels in one decoded sky (Radiance .hdr, PNG or JPEG): the largest published skies (16384 x
// 8192, 1.5 GiB as floats); a header asking for more is refused before pixel memory is taken.
inline constexpr std::uint64_t kSkyPixels = 16384ULL * 8192ULL;

// Numbers read from text tables (gaze traces, camera paths) are finite and within these.
// Times in milliseconds: 1e13 ms (317 years) still takes Unix-epoch stamps and keeps a double
// exact to a microsecond; a larger one is a corrupt file, and 1e300 overflowed frame counts.
inline constexpr double kTableTimeMs = 1e13;
// Camera positions and targets in scene units: a float camera past a million moves in steps of
// 1/16, and 1e300 became infinity (a NaN camera, a flat image).
inline constexpr double kSceneCoordinate = 1e6;

} // namespace gt::io::limits
