#pragma once
// Every file gazetrace writes goes through here: the bytes go to a temporary beside the target,
// every write(), the fsync() and the close() are checked, and only then does rename() replace the
// target. A failure anywhere (a full disk, a folder in the way, a read-only folder) removes the
// temporary, leaves an existing file as it was, and throws WriteError naming the file and the
// reason. No Vulkan, no OpenCV: the engine, the eye tracker and the apps all link it.
#include <cstddef>
#include <filesystem>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace gt::io {

class WriteError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

void writeFileAtomic(const std::filesystem::path& path, std::span<const std::byte> bytes);
void writeFileAtomic(const std::filesystem::path& path, std::string_view text);

// Text built up in memory and written by commit(); destroyed without commit(), nothing is
// written. The constructor fails at once when the target's folder does not exist, so a long
// job does not find out at its end.
class AtomicFile {
public:
    explicit AtomicFile(std::filesystem::path target);
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;
    [[nodiscard]] std::ostream& stream() noexcept { return mText; }
    [[nodiscard]] const std::filesystem::path& target() const noexcept { return mTarget; }
    void commit();

private:
    std::filesystem::path mTarget;
    std::ostringstream mText;
    bool mCommitted = false;
};

// A file another library writes by name (OpenCV's video writer, which picks the container from
// the extension): it writes to temp(), a unique name beside the target that keeps the target's
// extension, and commit() finishes it as writeFileAtomic does: the fsync() and the close() are
// checked, then rename() replaces the target. Until then nothing exists under the target's
// name; destroyed without commit() (a failed run), the temporary is removed and an existing
// file of that name stays as it was. The constructor fails at once when the target's folder
// does not exist or the target is a folder.
class StagedFile {
public:
    explicit StagedFile(std::filesystem::path target);
    ~StagedFile();
    StagedFile(const StagedFile&) = delete;
    StagedFile& operator=(const StagedFile&) = delete;
    [[nodiscard]] const std::filesystem::path& temp() const noexcept { return mTemp; }
    [[nodiscard]] const std::filesystem::path& target() const noexcept { return mTarget; }
    // Throws WriteError (the temporary removed) when nothing was written under temp(), or the
    // fsync or the rename fails.
    void commit();

private:
    std::filesystem::path mTarget;
    std::filesystem::path mTemp;
    bool mCommitted = false;
};

// The write-fault seam for tests: while set, writes fail with `error` (e.g. ENOSPC, a full
// disk) after `okBytes` bytes of the file (a StagedFile longer than that fails its commit()).
// GAZETRACE_WRITE_FAULT=enospc in the environment sets it for a whole process (command-line
// tests).
namespace testing {
void failWrites(int error, std::size_t okBytes = 0);
void clearWriteFaults();
} // namespace testing

} // namespace gt::io
