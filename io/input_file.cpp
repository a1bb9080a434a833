#include "input_file.hpp"

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <utility>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "file_kind.hpp"
#include "limits.hpp"

namespace gt::io {

namespace {

[[noreturn]] void refuse(const std::filesystem::path& path, const std::string& why) {
    throw InputError(path.string() + ": " + why);
}

// An open descriptor closed on every path out.
class Fd {
public:
    explicit Fd(int fd) noexcept : mFd(fd) {}
    ~Fd() {
        if (mFd >= 0) {
            ::close(mFd);
        }
    }
    Fd(Fd&& o) noexcept : mFd(std::exchange(o.mFd, -1)) {}
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    Fd& operator=(Fd&&) = delete;
    [[nodiscard]] int get() const noexcept { return mFd; }

private:
    int mFd;
};

// Opens without blocking (a FIFO with no writer would hang open()) and checks the descriptor:
// what is checked is what is read.
Fd openChecked(const std::filesystem::path& path, std::uint64_t maxBytes, struct stat& st) {
    Fd fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY));
    if (fd.get() < 0) {
        const int e = errno;
        if (e == ENOENT) {
            refuse(path, "no such file");
        }
        refuse(path, std::string("cannot open it (") + std::strerror(e) + ")");
    }
    if (::fstat(fd.get(), &st) != 0) {
        refuse(path, std::string("cannot read its status (") + std::strerror(errno) + ")");
    }
    if (!S_ISREG(st.st_mode)) {
        refuse(path, fileKind(st.st_mode) + ", not a regular file");
    }
    const auto size = static_cast<std::uint64_t>(st.st_size);
    if (size > maxBytes) {
        refuse(path, describeBytes(size) + " is over the " + describeBytes(maxBytes) +
                         " limit for this kind of file");
    }
    // A sparse file reads as zeros where nothing is allocated: refuse one that is mostly holes
    // rather than read gigabytes of nothing.
    const auto allocated = static_cast<std::uint64_t>(st.st_blocks) * 512U;
    if (size > 16 * limits::kMiB && allocated < size / 8) {
        refuse(path, "a sparse file (" + describeBytes(size) + " long, " +
                         describeBytes(allocated) + " on disk)");
    }
    // Reads block normally from here on (a regular file never would anyway).
    const int flags = ::fcntl(fd.get(), F_GETFL);
    if (flags >= 0) {
        (void)::fcntl(fd.get(), F_SETFL, flags & ~O_NONBLOCK);
    }
    return fd;
}

} // namespace

std::string describeBytes(std::uint64_t bytes) {
    constexpr std::array<const char*, 4> units{"KiB", "MiB", "GiB", "TiB"};
    if (bytes < 1024) {
        return std::to_string(bytes) + (bytes == 1 ? " byte" : " bytes");
    }
    double v = static_cast<double>(bytes) / 1024.0;
    std::size_t u = 0;
    while (v >= 1024.0 && u + 1 < units.size()) {
        v /= 1024.0;
        ++u;
    }
    std::array<char, 32> text{};
    std::snprintf(text.data(), text.size(), v < 10.0 ? "%.1f %s" : "%.0f %s", v, units[u]);
    return text.data();
}

std::string readInputFile(const std::filesystem::path& path, std::uint64_t maxBytes) {
    struct stat st {};
    const Fd fd = openChecked(path, maxBytes, st);
    std::string bytes;
    bytes.reserve(static_cast<std::size_t>(st.st_size));
    std::array<char, 1 << 16> chunk{};
    for (;;) {
        const ssize_t n = ::read(fd.get(), chunk.data(), chunk.size());
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            refuse(path, std::string("read failed (") + std::strerror(errno) + ")");
        }
        if (n == 0) {
            break;
        }
        if (bytes.size() + static_cast<std::size_t>(n) > maxBytes) {
            refuse(path, "grew past the " + describeBytes(maxBytes) + " limit while being read");
        }
        bytes.append(chunk.data(), static_cast<std::size_t>(n));
    }
    return bytes;
}

std::uint64_t checkInputFile(const std::filesystem::path& path, std::uint64_t maxBytes) {
    struct stat st {};
    const Fd fd = openChecked(path, maxBytes, st);
    return static_cast<std::uint64_t>(st.st_size);
}

bool sameFile(const std::filesystem::path& a, const std::filesystem::path& b) {
    struct stat sa {};
    struct stat sb {};
    if (::stat(a.c_str(), &sa) != 0 || ::stat(b.c_str(), &sb) != 0) {
        return false;
    }
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

} // namespace gt::io
