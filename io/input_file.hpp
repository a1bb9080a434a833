#pragma once
// Every file gazetrace reads comes in through here. A path names a regular file of bounded size,
// or it is refused with one line naming the file and the reason:
//  - a FIFO, a socket, a device or a folder would block forever or never end (/dev/zero); the
//    file is opened with O_NONBLOCK and checked with fstat() on the open descriptor, so neither
//    a FIFO's open nor a symlink swapped after the check can get past it;
//  - a file over the caller's limit, or a sparse one (most of its length unallocated), is refused
//    before any byte is read: a reader never grows a buffer without bound;
//  - a file that grows while it is read past the limit is refused as well.
// The limits themselves are named in io/limits.hpp and listed in docs/reliability.md.
// V4L2 capture devices are the one kind of non-regular input, and the camera source opens them
// itself.
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace gt::io {

class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The whole file as bytes. Throws InputError naming `path` and the reason.
[[nodiscard]] std::string readInputFile(const std::filesystem::path& path, std::uint64_t maxBytes);

// The same checks without reading, for the libraries that open a file by name themselves
// (OpenCV's video reader). Returns the file's size.
std::uint64_t checkInputFile(const std::filesystem::path& path, std::uint64_t maxBytes);

// "2.0 GiB", "512 KiB", "17 bytes": sizes in messages.
[[nodiscard]] std::string describeBytes(std::uint64_t bytes);

// True when both paths name one existing file (the same device and inode: hard links, symlinks
// and "./x" against "x" all count). An output that is one of the run's inputs is refused with it.
[[nodiscard]] bool sameFile(const std::filesystem::path& a, const std::filesystem::path& b);

} // namespace gt::io
