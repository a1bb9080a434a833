#include "atomic_write.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <random>

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include "input_file.hpp"

#include "file_kind.hpp"

namespace gt::io {

namespace {

namespace fs = std::filesystem;

struct Fault {
    std::atomic<int> error{0};
    std::atomic<std::size_t> okBytes{0};
};

Fault& fault() {
    static Fault f;
    static const bool fromEnvironment = [] {
        const char* e = std::getenv("GAZETRACE_WRITE_FAULT");
        if (e != nullptr && std::strcmp(e, "enospc") == 0) {
            f.error = ENOSPC;
        }
        return true;
    }();
    (void)fromEnvironment;
    return f;
}

[[noreturn]] void fail(const fs::path& path, const std::string& what, int error) {
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
            if (done >= ok) {
                return injected;
            }
            chunk = std::min(chunk, ok - done);
        }
        const ssize_t n = ::write(fd, data + done, chunk);
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            return errno;
        }
        if (n == 0) {
            return EIO;
        }
        done += static_cast<std::size_t>(n);
    }
    return 0;
}

fs::path folderOf(const fs::path& path) {
    return path.parent_path().empty() ? fs::path(".") : path.parent_path();
}

// What is at `path` itself (a symlink is not followed): nothing, a regular file or a symlink
// may be replaced by rename(); anything else is refused.
void requireReplaceable(const fs::path& path) {
    struct stat st {};
    if (::lstat(path.c_str(), &st) != 0) {
        return; // nothing there yet (or the folder fails later)
    }
    if (S_ISREG(st.st_mode) || S_ISLNK(st.st_mode)) {
        return;
    }
    if (S_ISDIR(st.st_mode)) {
        fail(path, "it is a folder", 0);
    }
    fail(path, "it is " + fileKind(st.st_mode) + ", not a regular file; refusing to replace it", 0);
}

void requireWritableFolder(const fs::path& path, const fs::path& folder) {
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) {
        fail(path, "folder " + folder.string() + " does not exist", 0);
    }
    if (::access(folder.c_str(), W_OK | X_OK) != 0) {
        fail(path, "folder " + folder.string() + " is not writable", errno);
    }
}

// 16 hex digits from the kernel's random source: a name nobody can guess ahead of the run.
std::string randomHex() {
    std::array<std::uint8_t, 8> bytes{};
    if (::getrandom(bytes.data(), bytes.size(), 0) != static_cast<ssize_t>(bytes.size())) {
        std::random_device device;
        for (auto& b : bytes) {
            b = static_cast<std::uint8_t>(device());
        }
    }
    static constexpr char kHex[] = "0123456789abcdef";
    std::string s;
    for (const std::uint8_t b : bytes) {
        s += kHex[b >> 4];
        s += kHex[b & 15];
    }
    return s;
}

// "STEM.tmp-<random>EXT" beside `target`, no longer than NAME_MAX bytes: the stem is shortened
// (at a UTF-8 character boundary) when the target's name is near the limit; the extension is
// kept for StagedFile (the video writer picks its container by it) unless it alone is too long.
fs::path temporaryName(const fs::path& target) {
    const std::string suffix = ".tmp-" + randomHex();
    std::string stem = target.stem().string();
    std::string ext = target.extension().string();
    if (suffix.size() + ext.size() + 1 > NAME_MAX) {
        ext.clear();
    }
    if (stem.empty() && ext.empty()) {
        stem = target.filename().string();
    }
    const std::size_t room = NAME_MAX - suffix.size() - ext.size();
    if (stem.size() > room) {
        std::size_t cut = room;
        while (cut > 0 && (static_cast<unsigned char>(stem[cut]) & 0xC0U) == 0x80U) {
            --cut;
        }
        stem.resize(cut);
    }
    return target.parent_path() / (stem + suffix + ext);
}

// A new regular file beside `target`, this process's alone: O_EXCL refuses any name that
// exists (a planted file or symlink), O_NOFOLLOW a symlink; a clash draws a new name.
int createTemporary(const fs::path& target, fs::path& temp) {
    for (int attempt = 0; attempt < 100; ++attempt) {
        temp = temporaryName(target);
        const int fd =
            ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (fd >= 0) {
            return fd;
        }
        if (errno != EEXIST) {
            const int e = errno;
            const fs::path folder = folderOf(target);
            if (e == EACCES || e == EROFS || e == EPERM) {
                fail(target, "folder " + folder.string() + " is not writable", e);
            }
            fail(target, "cannot create a file in " + folder.string(), e);
        }
    }
    fail(target, "no free temporary name in " + folderOf(target).string(), EEXIST);
}

// The temporary of a write in progress, removed unless released (every failure, and an
// exception unwinding through the write).
class TemporaryGuard {
public:
    explicit TemporaryGuard(const fs::path& temp) : mTemp(temp) {}
    ~TemporaryGuard() {
        if (mArmed) {
            ::unlink(mTemp.c_str());
        }
    }
    TemporaryGuard(const TemporaryGuard&) = delete;
    TemporaryGuard& operator=(const TemporaryGuard&) = delete;
    void release() noexcept { mArmed = false; }

private:
    const fs::path& mTemp;
    bool mArmed = true;
};

// rename() of a finished temporary over the target, the target checked once more right before.
void replaceWith(const fs::path& temp, const fs::path& target) {
    requireReplaceable(target);
    if (::rename(temp.c_str(), target.c_str()) != 0) {
        fail(target, "cannot replace it", errno);
    }
}

// The path with its symlinks and "."/".." resolved as far as it exists; spelled out (absolute,
// normalised) where it cannot be resolved, never empty: two outputs compare by it before either
// exists.
fs::path resolvedPath(const fs::path& path) {
    std::error_code ec;
    const fs::path absolute = fs::absolute(path, ec);
    if (ec) {
        return path.lexically_normal();
    }
    fs::path resolved = fs::weakly_canonical(absolute, ec);
    return ec ? absolute.lexically_normal() : resolved;
}

} // namespace

void checkOutputFile(const fs::path& path) {
    requireReplaceable(path);
    requireWritableFolder(path, folderOf(path));
}

void writeFileAtomic(const fs::path& path, std::span<const std::byte> bytes) {
    checkOutputFile(path);
    fs::path temp;
    const int fd = createTemporary(path, temp);
    TemporaryGuard guard(temp);
    auto abandon = [&](const std::string& what, int error) {
        ::close(fd);
        fail(path, what, error);
    };
    if (const int e = writeAll(fd, bytes.data(), bytes.size()); e != 0) {
        abandon("write failed", e);
    }
    if (::fsync(fd) != 0) {
        abandon("fsync failed", errno);
    }
    if (::close(fd) != 0) {
        fail(path, "close failed", errno);
    }
    replaceWith(temp, path);
    guard.release();
}

void writeFileAtomic(const fs::path& path, std::string_view text) {
    writeFileAtomic(path, std::as_bytes(std::span(text.data(), text.size())));
}

void refuseOutputThatIsInput(std::span<const RunFile> outputs, std::span<const RunFile> inputs) {
    auto named = [](const RunFile& f) { return f.option + " " + f.path.string(); };
    for (std::size_t i = 0; i < outputs.size(); ++i) {
        const RunFile& out = outputs[i];
        if (out.path.empty()) {
            continue;
        }
        for (const RunFile& in : inputs) {
            if (!in.path.empty() && sameFile(out.path, in.path)) {
                throw WriteError(named(out) + " is the same file as " + named(in) +
                                 ": refusing to overwrite an input");
            }
        }
        const fs::path resolved = resolvedPath(out.path);
        for (std::size_t j = i + 1; j < outputs.size(); ++j) {
            const RunFile& other = outputs[j];
            if (other.path.empty()) {
                continue;
            }
            const bool same =
                sameFile(out.path, other.path) || resolvedPath(other.path) == resolved;
            if (same) {
                throw WriteError(named(out) + " and " + named(other) +
                                 " name the same file: give each output its own");
            }
        }
    }
}

AtomicFile::AtomicFile(fs::path target) : mTarget(std::move(target)) {
    checkOutputFile(mTarget);
}

void AtomicFile::commit() {
    if (mCommitted) {
        return;
    }
    writeFileAtomic(mTarget, std::string_view(mText.view()));
    mCommitted = true;
}

StagedFile::StagedFile(fs::path target) : mTarget(std::move(target)) {
    checkOutputFile(mTarget);
    // Reserved now, so no other run (or planted link) can hold this name while the writer
    // opens it later.
    const int fd = createTemporary(mTarget, mTemp);
    ::close(fd);
}

StagedFile::~StagedFile() {
    if (mCommitted || mTemp.empty()) {
        return;
    }
    ::unlink(mTemp.c_str());
}

void StagedFile::commit() {
    if (mCommitted) {
        return;
    }
    auto abandon = [&](const std::string& what, int error) {
        ::unlink(mTemp.c_str());
        fail(mTarget, what, error);
    };
    const int fd = ::open(mTemp.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) {
        abandon("cannot open " + mTemp.string(), errno);
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size == 0) {
        ::close(fd);
        abandon("nothing was written", 0);
    }
    // The seam: the bytes another writer put there count as written here.
    const int injected = fault().error.load();
    if (injected != 0 && static_cast<std::size_t>(st.st_size) > fault().okBytes.load()) {
        ::close(fd);
        abandon("write failed", injected);
    }
    if (::fsync(fd) != 0) {
        const int e = errno;
        ::close(fd);
        abandon("fsync failed", e);
    }
    if (::close(fd) != 0) {
        abandon("close failed", errno);
    }
    try {
        replaceWith(mTemp, mTarget);
    } catch (const WriteError&) {
        ::unlink(mTemp.c_str());
        throw;
    }
    mCommitted = true;
}

StagedFolder::StagedFolder(fs::path target) : mTarget(std::move(target)) {
    if (!mTarget.has_filename()) {
        mTarget = mTarget.parent_path(); // "out/frames/"
    }
    std::error_code ec;
    struct stat st {};
    if (::stat(mTarget.c_str(), &st) == 0 && !S_ISDIR(st.st_mode)) {
        fail(mTarget,
             "it is " + (S_ISREG(st.st_mode) ? std::string("a file") : fileKind(st.st_mode)) +
                 ", not a folder",
             0);
    }
    // The folders above the target, made as a run that writes into out/eval always has; the
    // ones made here are removed again (if empty) when the run fails.
    for (fs::path p = mTarget.parent_path(); !p.empty(); p = p.parent_path()) {
        if (fs::exists(p, ec) || ec) {
            break; // there, or not ours to judge (not searchable)
        }
        mCreatedParents.push_back(p);
        if (p == p.parent_path()) {
            break;
        }
    }
    if (!mCreatedParents.empty()) {
        fs::create_directories(mTarget.parent_path(), ec);
        if (ec) {
            mCreatedParents.clear();
            fail(mTarget, "cannot create folder " + mTarget.parent_path().string(), ec.value());
        }
    }
    const fs::path folder = folderOf(mTarget);
    for (int attempt = 0; attempt < 100; ++attempt) {
        mTemp = temporaryName(mTarget);
        if (::mkdir(mTemp.c_str(), 0777) == 0) {
            return;
        }
        if (errno == EEXIST) {
            continue;
        }
        const int e = errno;
        mTemp.clear();
        for (const fs::path& p : mCreatedParents) {
            fs::remove(p, ec);
        }
        if (e == EACCES || e == EROFS || e == EPERM) {
            fail(mTarget, "folder " + folder.string() + " is not writable", e);
        }
        fail(mTarget, "cannot create a folder in " + folder.string(), e);
    }
    fail(mTarget, "no free temporary name in " + folder.string(), EEXIST);
}

StagedFolder::~StagedFolder() {
    if (mCommitted) {
        return;
    }
    std::error_code ec;
    if (!mTemp.empty()) {
        fs::remove_all(mTemp, ec); // this run's folder: only what it wrote
    }
    for (const fs::path& p : mCreatedParents) {
        fs::remove(p, ec); // only while empty
    }
}

void StagedFolder::commit() {
    if (mCommitted) {
        return;
    }
    struct stat st {};
    if (::lstat(mTarget.c_str(), &st) != 0) {
        if (::rename(mTemp.c_str(), mTarget.c_str()) != 0) {
            fail(mTarget, "cannot create it", errno);
        }
        mCommitted = true;
        return;
    }
    std::error_code ec;
    if (!fs::is_directory(mTarget, ec)) {
        fail(mTarget, "it is no longer a folder", 0);
    }
    std::vector<fs::path> names;
    for (const auto& entry : fs::directory_iterator(mTemp, ec)) {
        names.push_back(entry.path().filename());
    }
    if (ec) {
        fail(mTarget, "cannot list " + mTemp.string(), ec.value());
    }
    std::sort(names.begin(), names.end());
    for (const fs::path& name : names) {
        requireReplaceable(mTarget / name);
    }
    for (const fs::path& name : names) {
        const fs::path from = mTemp / name;
        const fs::path to = mTarget / name;
        if (::rename(from.c_str(), to.c_str()) != 0) {
            fail(to, "cannot replace it", errno);
        }
    }
    ::rmdir(mTemp.c_str());
    mCommitted = true;
}

int writeAll(int fd, std::span<const std::byte> bytes) {
    return writeAll(fd, bytes.data(), bytes.size());
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
