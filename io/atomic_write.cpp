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

// ".tmp<pid>_<n>": unique per process and call, since two processes may write the same cache
// file at once.
std::string temporarySuffix() {
    static std::atomic<unsigned> counter{0};
    return ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
}

void requireFolder(const std::filesystem::path& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) fail(path, "it is a folder", 0);
    const std::filesystem::path parent =
        path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
    if (!std::filesystem::is_directory(parent, ec)) {
        fail(path, "folder " + parent.string() + " does not exist", 0);
    }
}

} // namespace

void writeFileAtomic(const std::filesystem::path& path, std::span<const std::byte> bytes) {
    requireFolder(path);
    const std::filesystem::path parent =
        path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
    std::error_code ec;
    std::filesystem::path temp = path;
    temp += temporarySuffix();
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

StagedFile::StagedFile(std::filesystem::path target) : mTarget(std::move(target)) {
    requireFolder(mTarget);
    // The writer picks the format from the extension, so the temporary keeps it.
    mTemp = mTarget.parent_path() /
            (mTarget.stem().string() + temporarySuffix() + mTarget.extension().string());
}

StagedFile::~StagedFile() {
    if (mCommitted) return;
    std::error_code ec;
    std::filesystem::remove(mTemp, ec);
}

void StagedFile::commit() {
    if (mCommitted) return;
    std::error_code ec;
    auto abandon = [&](const std::string& what, int error) {
        std::filesystem::remove(mTemp, ec);
        fail(mTarget, what, error);
    };
    if (!std::filesystem::is_regular_file(mTemp, ec)) abandon("nothing was written", 0);
    const std::uintmax_t size = std::filesystem::file_size(mTemp, ec);
    if (ec) abandon("cannot read the size of " + mTemp.string(), ec.value());
    // The seam: the bytes another writer put there count as written here.
    if (const int injected = fault().error.load(); injected != 0 && size > fault().okBytes.load()) {
        abandon("write failed", injected);
    }
    const int fd = ::open(mTemp.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) abandon("cannot open " + mTemp.string(), errno);
    if (::fsync(fd) != 0) {
        const int e = errno;
        ::close(fd);
        abandon("fsync failed", e);
    }
    if (::close(fd) != 0) abandon("close failed", errno);
    std::filesystem::rename(mTemp, mTarget, ec);
    if (ec) abandon("cannot replace it", ec.value());
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
