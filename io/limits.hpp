#pragma once
// Every size and count limit gazetrace applies to what it reads, in one place; docs/limits.md
// lists them with the reason for each. A limit is refused with one line naming the file or the
// value and the limit.
#include <cstdint>

namespace gt::io::limits {

inline constexpr std::uint64_t kKiB = 1024;
inline constexpr std::uint64_t kMiB = 1024 * kKiB;
inline constexpr std::uint64_t kGiB = 1024 * kMiB;

// Text tables (gaze traces, camera paths, truth CSVs, target lists) and small JSON documents
// (calibrations): a day of 1 kHz gaze samples is ~3 GB, far beyond any run; an hour is ~150 MB.
inline constexpr std::uint64_t kTextTableBytes = 256 * kMiB;
inline constexpr std::uint64_t kJsonDocumentBytes = 64 * kMiB;
// A .gltf document or a GLB file, and each external buffer it names.
inline constexpr std::uint64_t kGltfDocumentBytes = 256 * kMiB;
inline constexpr std::uint64_t kGltfBufferBytes = 2 * kGiB;
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

} // namespace gt::io::limits
