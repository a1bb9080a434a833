// The one file writer (io/atomic_write.hpp): a full disk, a folder in the way or a missing folder
// fail with the reason, keep an existing file as it was, and leave no temporary behind.
#include <cerrno>
#include <fstream>
#include <string>

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

} // namespace
} // namespace gt
