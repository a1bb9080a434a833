#pragma once
// A FIFO with no writer, given to a loader as its input file: a loader that opens it as a plain
// file waits in open() forever. The FIFO's guard opens the write end itself after a grace
// period, so such a loader sees an empty file and its test fails instead of hanging.
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <thread>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

namespace gt::test {

class WriterlessFifo {
public:
    explicit WriterlessFifo(std::filesystem::path path,
                            std::chrono::milliseconds grace = std::chrono::seconds(3))
        : mPath(std::move(path)) {
        EXPECT_EQ(::mkfifo(mPath.c_str(), 0600), 0) << mPath;
        mGuard = std::thread([this, grace] { unblockAfter(grace); });
    }
    ~WriterlessFifo() {
        {
            const std::lock_guard<std::mutex> lock(mMutex);
            mDone = true;
        }
        mWake.notify_all();
        mGuard.join();
    }
    WriterlessFifo(const WriterlessFifo&) = delete;
    WriterlessFifo& operator=(const WriterlessFifo&) = delete;

    [[nodiscard]] const std::filesystem::path& path() const noexcept { return mPath; }
    // True when a loader waited for a writer: the guard had to open the write end.
    [[nodiscard]] bool blockedALoader() const {
        const std::lock_guard<std::mutex> lock(mMutex);
        return mUnblocked;
    }

private:
    void unblockAfter(std::chrono::milliseconds grace) {
        std::unique_lock<std::mutex> lock(mMutex);
        if (mWake.wait_for(lock, grace, [this] { return mDone; })) return;
        // Open and close the write end until released: a reader waiting in open() wakes and
        // then reads end-of-file. O_NONBLOCK fails (ENXIO) while no reader has it open.
        while (!mDone) {
            const int fd = ::open(mPath.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
            if (fd >= 0) {
                struct stat st {};
                // Only the FIFO counts: a loader may have replaced it with a file by now.
                if (::fstat(fd, &st) == 0 && S_ISFIFO(st.st_mode)) mUnblocked = true;
                ::close(fd);
            }
            mWake.wait_for(lock, std::chrono::milliseconds(50), [this] { return mDone; });
        }
    }

    std::filesystem::path mPath;
    mutable std::mutex mMutex;
    std::condition_variable mWake;
    bool mDone = false;
    bool mUnblocked = false;
    std::thread mGuard;
};

} // namespace gt::test
