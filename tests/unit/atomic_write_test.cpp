// The one file writer (io/atomic_write.hpp): a full disk, a folder in the way or a missing folder
// fail with the reason, keep an existing file as it was, and leave no temporary behind.
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "atomic_write.hpp"
#include "support/bad_files.hpp"
#include "support/gpu_test_context.hpp"

namespace gt {
namespace {

std::string readAll(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool onlyFile(const std::filesystem::path& dir, const std::string& name) {
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        if (e.path().filename() != name) return false;
        ++n;
    }
    return n == 1;
}

struct ClearFaults {
    ~ClearFaults() { io::testing::clearWriteFaults(); }
};

TEST(AtomicWrite, FullDiskKeepsTheOldFileAndLeavesNothing) {
    const ClearFaults clear;
    const auto dir = test::tempDir("atomic_full");
    const auto file = dir / "out.png";
    io::writeFileAtomic(file, std::string("old contents"));
    ASSERT_EQ(readAll(file), "old contents");
    const std::string big(100000, 'x');
    for (const std::size_t ok : {std::size_t{0}, std::size_t{4096}}) {
        io::testing::failWrites(ENOSPC, ok); // the disk fills after `ok` bytes
        const std::string e =
            test::thrownMessage<io::WriteError>([&] { io::writeFileAtomic(file, big); });
        EXPECT_NE(e.find("out.png"), std::string::npos) << e;
        EXPECT_NE(e.find("No space left"), std::string::npos) << e;
        EXPECT_EQ(readAll(file), "old contents"); // untouched
        EXPECT_TRUE(onlyFile(dir, "out.png"));    // no temporary left
    }
    io::testing::clearWriteFaults();
    io::writeFileAtomic(file, big);
    EXPECT_EQ(readAll(file), big);
}

TEST(AtomicWrite, FolderInTheWayOrMissingIsNamed) {
    const auto dir = test::tempDir("atomic_folder");
    std::filesystem::create_directories(dir / "x.png");
    const std::string e = test::thrownMessage<io::WriteError>(
        [&] { io::writeFileAtomic(dir / "x.png", std::string("a")); });
    EXPECT_NE(e.find("is a folder"), std::string::npos) << e;
    EXPECT_THROW(io::writeFileAtomic(dir / "none" / "y.png", std::string("a")), io::WriteError);
    EXPECT_THROW(io::AtomicFile(dir / "none" / "z.csv"), io::WriteError); // at once
    // Destroyed without commit: nothing written.
    {
        io::AtomicFile f(dir / "later.csv");
        f.stream() << "a,b\n";
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "later.csv"));
    io::AtomicFile g(dir / "now.csv");
    g.stream() << "a,b\n";
    g.commit();
    EXPECT_EQ(readAll(dir / "now.csv"), "a,b\n");
}

// A file another library writes by name (a video): nothing under the target's name until
// commit(), then the whole file; a run that fails (no commit, or a full disk at the commit)
// leaves an existing file as it was and no temporary.
TEST(AtomicWrite, StagedFileAppearsOnlyWhenCommitted) {
    const ClearFaults clear;
    const auto dir = test::tempDir("atomic_staged");
    const auto file = dir / "clip.mkv";
    {
        io::StagedFile staged(file);
        EXPECT_EQ(staged.temp().parent_path(), dir);
        EXPECT_EQ(staged.temp().extension(), ".mkv"); // the writer picks the container by it
        std::ofstream(staged.temp(), std::ios::binary) << "first clip";
        EXPECT_FALSE(std::filesystem::exists(file));
        staged.commit();
    }
    EXPECT_EQ(readAll(file), "first clip");
    EXPECT_TRUE(onlyFile(dir, "clip.mkv"));
    {
        io::StagedFile abandoned(file);
        std::ofstream(abandoned.temp(), std::ios::binary) << "half a clip";
    }
    EXPECT_EQ(readAll(file), "first clip");
    EXPECT_TRUE(onlyFile(dir, "clip.mkv"));
    io::testing::failWrites(ENOSPC);
    {
        io::StagedFile full(file);
        std::ofstream(full.temp(), std::ios::binary) << "second clip";
        const std::string e = test::thrownMessage<io::WriteError>([&] { full.commit(); });
        EXPECT_NE(e.find("No space left"), std::string::npos) << e;
    }
    EXPECT_EQ(readAll(file), "first clip");
    EXPECT_TRUE(onlyFile(dir, "clip.mkv"));
    io::testing::clearWriteFaults();
    io::StagedFile empty(file); // the writer never created it
    EXPECT_THROW(empty.commit(), io::WriteError);
    EXPECT_EQ(readAll(file), "first clip");
    EXPECT_THROW(io::StagedFile(dir / "none" / "x.mkv"), io::WriteError); // at once
}

bool isCharDevice(const std::filesystem::path& p) {
    struct stat st {};
    return ::lstat(p.c_str(), &st) == 0 && S_ISCHR(st.st_mode);
}

// A device node, a FIFO or a folder at the output path is refused, named, and left as it was:
// rename() would have put a regular file in place of /dev/null.
TEST(AtomicWrite, OutputThatIsNotARegularFileIsRefused) {
    const auto dir = test::tempDir("atomic_nonregular");
    std::vector<std::pair<std::filesystem::path, std::string>> nodes;
    if (::mknod((dir / "null").c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0) {
        nodes.emplace_back(dir / "null", "a character device");
    } // else not root: the FIFO stands for every non-regular kind
    ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0666), 0);
    nodes.emplace_back(dir / "fifo", "a FIFO");
    std::filesystem::create_directory(dir / "folder");
    nodes.emplace_back(dir / "folder", "a folder");
    for (const auto& entry : nodes) {
        // Plain references: clang does not let a lambda capture a structured binding.
        const std::filesystem::path& node = entry.first;
        const std::string& kind = entry.second;
        for (const auto& write : std::vector<std::function<void()>>{
                 [&] { io::writeFileAtomic(node, std::string("452 KB")); },
                 [&] { io::AtomicFile f(node); }, [&] { io::StagedFile f(node); }}) {
            const std::string e = test::thrownMessage<io::WriteError>(write);
            EXPECT_NE(e.find(node.string()), std::string::npos) << e;
            EXPECT_NE(e.find(kind), std::string::npos) << e;
        }
    }
    if (nodes.front().second == "a character device") {
        EXPECT_TRUE(isCharDevice(dir / "null"));
    }
    EXPECT_TRUE(std::filesystem::is_fifo(dir / "fifo"));
    EXPECT_TRUE(std::filesystem::is_directory(dir / "folder"));
}

// A symlink at the output path is replaced itself; the file it points to is never written.
TEST(AtomicWrite, SymlinkAtTheOutputIsReplacedNotWrittenThrough) {
    const auto dir = test::tempDir("atomic_symlink");
    io::writeFileAtomic(dir / "victim", std::string("victim"));
    std::filesystem::create_symlink(dir / "victim", dir / "out.csv");
    io::writeFileAtomic(dir / "out.csv", std::string("new"));
    EXPECT_EQ(readAll(dir / "victim"), "victim");
    EXPECT_FALSE(std::filesystem::is_symlink(dir / "out.csv"));
    EXPECT_EQ(readAll(dir / "out.csv"), "new");
}

// Symlinks planted under the names a temporary once had (OUT.tmp<pid>_<n>) redirect nothing:
// temporaries are created O_EXCL|O_NOFOLLOW under a random name.
TEST(AtomicWrite, PlantedTemporaryNamesRedirectNothing) {
    const ClearFaults clear;
    const auto dir = test::tempDir("atomic_planted");
    io::writeFileAtomic(dir / "victim", std::string("victim"));
    const std::string pid = std::to_string(::getpid());
    for (int n = 0; n < 2000; ++n) {
        for (const std::string stem : {"out.csv", "clip"}) {
            const std::string ext = stem == "clip" ? ".mkv" : "";
            std::filesystem::create_symlink(
                dir / "victim", dir / (stem + ".tmp" + pid + "_" + std::to_string(n) + ext));
        }
    }
    io::writeFileAtomic(dir / "out.csv", std::string("new"));
    EXPECT_EQ(readAll(dir / "out.csv"), "new");
    io::StagedFile a(dir / "clip.mkv");
    io::StagedFile b(dir / "clip.mkv");
    // Each reserved at once, each its own: two runs on one output never share a partial file.
    EXPECT_TRUE(std::filesystem::is_regular_file(std::filesystem::symlink_status(a.temp())));
    EXPECT_NE(a.temp(), b.temp());
    EXPECT_EQ(a.temp().extension(), ".mkv");
    EXPECT_EQ(a.temp().string().find(pid), std::string::npos) << a.temp();
    std::ofstream(a.temp(), std::ios::binary) << "clip a";
    a.commit();
    EXPECT_EQ(readAll(dir / "victim"), "victim");
    EXPECT_EQ(readAll(dir / "clip.mkv"), "clip a");
    EXPECT_THROW(b.commit(), io::WriteError); // its writer never wrote
    EXPECT_EQ(readAll(dir / "clip.mkv"), "clip a");
}

// Names of up to NAME_MAX (255) bytes: the temporary's stem is shortened to fit, its extension
// kept.
TEST(AtomicWrite, NamesUpToNameMaxAreWritten) {
    const auto dir = test::tempDir("atomic_long");
    for (const std::size_t length : {250U, 254U, 255U}) {
        const std::string name = std::string(length - 4, 'n') + ".csv";
        io::writeFileAtomic(dir / name, std::string("rows"));
        EXPECT_EQ(readAll(dir / name), "rows") << length;
        const std::string clip = std::string(length - 4, 'v') + ".mkv";
        io::StagedFile staged(dir / clip);
        EXPECT_LE(staged.temp().filename().string().size(), 255U);
        EXPECT_EQ(staged.temp().extension(), ".mkv");
        std::ofstream(staged.temp(), std::ios::binary) << "clip";
        staged.commit();
        EXPECT_EQ(readAll(dir / clip), "clip") << length;
    }
    // Shortened at a character, not inside one: 2-byte characters up to 254 bytes.
    std::string wide;
    while (wide.size() + 2 <= 254)
        wide += "\xc3\xa9";
    io::writeFileAtomic(dir / wide, std::string("e"));
    EXPECT_EQ(readAll(dir / wide), "e");
}

// An output naming an input (by any spelling or link), or two outputs naming one file, are
// refused with one line naming both.
TEST(AtomicWrite, OutputThatIsAnInputIsRefused) {
    const auto dir = test::tempDir("atomic_same");
    io::writeFileAtomic(dir / "in.mkv", std::string("clip"));
    std::filesystem::create_hard_link(dir / "in.mkv", dir / "hard.mkv");
    std::filesystem::create_symlink(dir / "in.mkv", dir / "soft.mkv");
    const std::vector<io::RunFile> inputs{{"--source", dir / "in.mkv"}, {"--truth", ""}};
    for (const auto& spelling :
         {dir / "in.mkv", dir / "." / "in.mkv", dir / "hard.mkv", dir / "soft.mkv"}) {
        const std::vector<io::RunFile> outputs{{"--out", ""}, {"--pupils", spelling}};
        const std::string e = test::thrownMessage<io::WriteError>(
            [&] { io::refuseOutputThatIsInput(outputs, inputs); });
        EXPECT_NE(e.find("--pupils " + spelling.string()), std::string::npos) << e;
        EXPECT_NE(e.find("--source " + (dir / "in.mkv").string()), std::string::npos) << e;
    }
    // Two outputs, neither written yet, one file.
    const std::vector<io::RunFile> twice{{"--out", dir / "x.csv"},
                                         {"--truth", dir / "sub" / ".." / "x.csv"}};
    std::filesystem::create_directory(dir / "sub");
    const std::string e =
        test::thrownMessage<io::WriteError>([&] { io::refuseOutputThatIsInput(twice, {}); });
    EXPECT_NE(e.find("--out"), std::string::npos) << e;
    EXPECT_NE(e.find("--truth"), std::string::npos) << e;
    const std::vector<io::RunFile> apart{{"--out", dir / "x.csv"}, {"--truth", dir / "y.csv"}};
    EXPECT_NO_THROW(io::refuseOutputThatIsInput(apart, inputs));
    EXPECT_EQ(readAll(dir / "in.mkv"), "clip");
}

// A folder this user cannot write is named as such, at once (the video writer only said
// "cannot open a lossless FFV1 writer"). Root writes anywhere, so the check runs as nobody.
TEST(AtomicWrite, ReadOnlyFolderIsNamed) {
    const auto dir = test::tempDir("atomic_readonly");
    std::filesystem::create_directory(dir / "ro");
    std::filesystem::permissions(
        dir / "ro", std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec |
                        std::filesystem::perms::others_read | std::filesystem::perms::others_exec |
                        std::filesystem::perms::group_read | std::filesystem::perms::group_exec);
    std::filesystem::create_directory(dir / "private");
    std::filesystem::permissions(dir / "private", std::filesystem::perms::owner_all);
    const auto tryAll = [&] {
        if (::geteuid() == 0 && (::setgid(65534) != 0 || ::setuid(65534) != 0)) std::exit(3);
        int named = 0;
        for (const auto& write : std::vector<std::function<void()>>{
                 [&] { io::StagedFile f(dir / "ro" / "clip.mkv"); },
                 [&] { io::AtomicFile f(dir / "ro" / "truth.csv"); },
                 [&] { io::writeFileAtomic(dir / "ro" / "x.json", std::string("{}")); },
                 [&] { io::StagedFolder f(dir / "ro" / "frames"); }}) {
            try {
                write();
            } catch (const io::WriteError& e) {
                const std::string m = e.what();
                if (m.find("folder " + (dir / "ro").string() + " is not writable") !=
                    std::string::npos)
                    ++named;
                else
                    std::cerr << m << "\n";
            }
        }
        // Outputs in a folder this user cannot search are still told apart.
        const std::vector<io::RunFile> apart{{"--out", dir / "private" / "a.mkv"},
                                             {"--truth", dir / "private" / "b.csv"}};
        try {
            io::refuseOutputThatIsInput(apart, {});
        } catch (const io::WriteError& e) {
            std::cerr << e.what() << "\n";
            std::exit(2);
        }
        std::exit(named == 4 ? 0 : 1);
    };
    EXPECT_EXIT(tryAll(), ::testing::ExitedWithCode(0), "");
}

// A folder run (render's frames, eval's pictures) writes into a temporary folder: a run that
// fails leaves the earlier run's files as they were and no temporary; one that succeeds
// replaces the files it wrote and keeps the ones it did not write.
TEST(AtomicWrite, FailedFolderRunKeepsTheEarlierRun) {
    const auto dir = test::tempDir("atomic_folder_run");
    const auto frames = dir / "out" / "frames";
    {
        io::StagedFolder run(frames); // the folders above are made too
        io::writeFileAtomic(run.file("frame_0000.png"), std::string("old 0"));
        io::writeFileAtomic(run.file("frame_0001.png"), std::string("old 1"));
        EXPECT_FALSE(std::filesystem::exists(frames));
        run.commit();
    }
    io::writeFileAtomic(frames / "notes.txt", std::string("mine"));
    {
        io::StagedFolder failed(frames);
        io::writeFileAtomic(failed.file("frame_0000.png"), std::string("new 0"));
    } // destroyed without commit: a failed or interrupted run
    EXPECT_EQ(readAll(frames / "frame_0000.png"), "old 0");
    EXPECT_EQ(readAll(frames / "frame_0001.png"), "old 1");
    EXPECT_TRUE(onlyFile(dir / "out", "frames"));
    {
        io::StagedFolder shorter(frames);
        io::writeFileAtomic(shorter.file("frame_0000.png"), std::string("new 0"));
        shorter.commit();
    }
    EXPECT_EQ(readAll(frames / "frame_0000.png"), "new 0");
    EXPECT_EQ(readAll(frames / "frame_0001.png"), "old 1"); // not this run's to delete
    EXPECT_EQ(readAll(frames / "notes.txt"), "mine");
    EXPECT_TRUE(onlyFile(dir / "out", "frames"));
    // A failed first run into folders that did not exist leaves none of them.
    { io::StagedFolder first(dir / "a" / "b" / "frames"); }
    EXPECT_FALSE(std::filesystem::exists(dir / "a"));
    io::writeFileAtomic(dir / "file", std::string("x"));
    const std::string e =
        test::thrownMessage<io::WriteError>([&] { io::StagedFolder f(dir / "file"); });
    EXPECT_NE(e.find("not a folder"), std::string::npos) << e;
}

} // namespace
} // namespace gt
