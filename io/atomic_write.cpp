#include "atomic_write.hpp"

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>

#include <fcntl.h>
#include <unistd.h>

namespace gt::io {

namespace {

struct Fault {
    std::atomic<int> error{0};
    std::atomic<std::size_t> okBytes{0};
};

Fault& fault() {
    static Fault f;
    static const bool fromEnvironment = [] {
        const char* e = std::getenv("GAZETRACE_WRITE_FAULT");
        if (e != nullptr && std::strcmp(e, "enospc") == 0) f.error = ENOSPC;
        return true;
    }();
    (void)fromEnvironment;
    return f;
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what, int error) {
    throw WriteError("cannot write " + path.string() + ": " + what +
                     (error != 0 ? std::string(" (") + std::strerror(error) + ")" : ""));
}

// write() until done; EINTR retried; the seam may fail it.
int writeAll(int fd, const std::byte* data, std::size_t size) {
    std::size_t done = 0;
    while (done < size) {
        std::size_t chunk = size - done;
        const int injected = fault().error.load();
        if (injected != 0) {
            const std::size_t ok = fault().okBytes.load();
            if (done >= ok) return injected;
            chunk = std::min(chunk, ok - done);
        }
        const ssize_t n = ::write(fd, data + done, chunk);
        if (n < 0) {
            if (errno == EINTR) continue;
            return errno;
        }
        if (n == 0) return EIO;
        done += static_cast<std::size_t>(n);
    }
    return 0;
}

} // namespace

void writeFileAtomic(const std::filesystem::path& path, std::span<const std::byte> bytes) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) fail(path, "it is a folder", 0);
    const std::filesystem::path parent =
        path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
    if (!std::filesystem::is_directory(parent, ec)) {
        fail(path, "folder " + parent.string() + " does not exist", 0);
    }
    // Unique per process and call: two processes may write the same cache file at once.
    static std::atomic<unsigned> counter{0};
    std::filesystem::path temp = path;
    temp += ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) fail(path, "cannot create a file in " + parent.string(), errno);
    auto abandon = [&](const std::string& what, int error) {
        ::close(fd);
        std::filesystem::remove(temp, ec);
        fail(path, what, error);
    };
    if (const int e = writeAll(fd, bytes.data(), bytes.size()); e != 0) abandon("write failed", e);
    if (::fsync(fd) != 0) abandon("fsync failed", errno);
    if (::close(fd) != 0) {
        const int e = errno;
        std::filesystem::remove(temp, ec);
        fail(path, "close failed", e);
    }
    std::filesystem::rename(temp, path, ec);
    if (ec) {
        std::filesystem::remove(temp, ec);
        fail(path, "cannot replace it", ec.value());
    }
}

void writeFileAtomic(const std::filesystem::path& path, std::string_view text) {
    writeFileAtomic(path, std::as_bytes(std::span(text.data(), text.size())));
}

AtomicFile::AtomicFile(std::filesystem::path target) : mTarget(std::move(target)) {
    const std::filesystem::path parent = mTarget.parent_path();
    std::error_code ec;
    if (!parent.empty() && !std::filesystem::is_directory(parent, ec)) {
        fail(mTarget, "folder " + parent.string() + " does not exist", 0);
    }
}

void AtomicFile::commit() {
    if (mCommitted) return;
    writeFileAtomic(mTarget, std::string_view(mText.view()));
    mCommitted = true;
}

namespace testing {
void failWrites(int error, std::size_t okBytes) {
    fault().okBytes = okBytes;
    fault().error = error;
}
void clearWriteFaults() {
    fault().error = 0;
    fault().okBytes = 0;
}
} // namespace testing

} // namespace gt::io
