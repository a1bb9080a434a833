#pragma once
// Every file gazetrace writes goes through here: the bytes go to a temporary beside the target,
// every write(), the fsync() and the close() are checked, and only then does rename() replace the
// target. A failure anywhere (a full disk, a folder in the way, a read-only folder) removes the
// temporary, leaves an existing file as it was, and throws WriteError naming the file and the
// reason. No Vulkan, no OpenCV: the engine, the eye tracker and the apps all link it.
//
// The one rule for an output path:
//  - its folder must exist and be writable;
//  - it may not exist yet, or be a regular file, which is replaced whole;
//  - anything else there (a device such as /dev/null, a FIFO, a socket, a folder) is refused with
//    one line naming the path: the rename would put a regular file in its place;
//  - a symlink there is replaced itself, never written through: the file it points to stays as
//    it was (rename() replaces the name, not what it names);
//  - an output that names one of the run's inputs, or two outputs of one run that name one file,
//    are refused before any work (refuseOutputThatIsInput).
// Temporaries are created with O_CREAT|O_EXCL|O_NOFOLLOW under an unpredictable name
// ("STEM.tmp-<16 random hex digits>EXT", the stem shortened so the name fits NAME_MAX), so a
// file or a symlink planted under a guessed name in a shared folder is never written through.
// Every type here removes what it created when it is destroyed without commit() (a failed or
// interrupted run that unwinds), and never removes anything it did not create.
#include <cstddef>
#include <filesystem>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace gt::io {

class WriteError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

void writeFileAtomic(const std::filesystem::path& path, std::span<const std::byte> bytes);
void writeFileAtomic(const std::filesystem::path& path, std::string_view text);

// The output rule above, checked without writing: for a command that writes its output only at
// the end of a long run (bench --json, demo --log), so it fails at the start instead.
void checkOutputFile(const std::filesystem::path& path);

// One file a run names on its command line: the option that named it ("--pupils") and its path.
struct RunFile {
    std::string option;
    std::filesystem::path path;
};

// Throws WriteError, one line naming both, when an output names one of the inputs (the same file
// by io::sameFile: hard links, symlinks and other spellings count) or two outputs name one file
// (the same file, or the same path once resolved, for outputs that do not exist yet). Empty
// paths are skipped. Every command with both inputs and outputs calls it before any work.
void refuseOutputThatIsInput(std::span<const RunFile> outputs, std::span<const RunFile> inputs);

// Text built up in memory and written by commit(); destroyed without commit(), nothing is
// written. The constructor checks the output rule at once (checkOutputFile), so a long job does
// not find out at its end.
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
// checked, then rename() replaces the target. The constructor checks the output rule and
// reserves temp() as an empty file of this process (O_EXCL), so two runs on one output never
// share a partial file; a folder that is not writable fails here, naming it. Until commit()
// nothing exists under the target's name; destroyed without commit() (a failed run), the
// temporary is removed and an existing file of that name stays as it was.
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

// A folder of files written one by one over a run (render's frame_NNNN.png, eval's PNGs and
// eval.json). The files go into temp(), a new folder beside the target ("NAME.tmp-<random>");
// commit() moves them in:
//  - no target yet: temp() is renamed to it, all at once;
//  - a target folder (or a symlink to one): each file is renamed into it, replacing the earlier
//    run's file of that name (each rename atomic), then the emptied temp() is removed. Files in
//    the target that this run did not write stay as they were: an input kept there (eval
//    --reference out/eval/reference.png) or the later frames of an earlier, longer run. Nothing
//    the run did not create is ever deleted.
// The constructor refuses a target that exists and is not a folder, and creates the missing
// folders above it (removed again, if still empty, when the run fails). Destroyed without
// commit() (a failed or interrupted run), temp() and everything in it are removed and the target
// stays as the earlier run left it.
class StagedFolder {
public:
    explicit StagedFolder(std::filesystem::path target);
    ~StagedFolder();
    StagedFolder(const StagedFolder&) = delete;
    StagedFolder& operator=(const StagedFolder&) = delete;
    [[nodiscard]] const std::filesystem::path& temp() const noexcept { return mTemp; }
    [[nodiscard]] const std::filesystem::path& target() const noexcept { return mTarget; }
    // Where a file named `name` is written during the run.
    [[nodiscard]] std::filesystem::path file(const std::string& name) const { return mTemp / name; }
    void commit();

private:
    std::filesystem::path mTarget;
    std::filesystem::path mTemp;
    std::vector<std::filesystem::path> mCreatedParents; // deepest first
    bool mCommitted = false;
};

// write() until all of `bytes` is out (EINTR retried), through the write-fault seam below;
// returns 0 or the errno that stopped it. For a file kept open and written in place (the study's
// journal, appended line by line), where the rules above do not apply.
[[nodiscard]] int writeAll(int fd, std::span<const std::byte> bytes);

// The write-fault seam for tests: while set, writes fail with `error` (e.g. ENOSPC, a full
// disk) after `okBytes` bytes of the file (a StagedFile longer than that fails its commit()).
// GAZETRACE_WRITE_FAULT=enospc in the environment sets it for a whole process (command-line
// tests).
namespace testing {
void failWrites(int error, std::size_t okBytes = 0);
void clearWriteFaults();
} // namespace testing

} // namespace gt::io
