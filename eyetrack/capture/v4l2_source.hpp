#pragma once
// V4L2 camera capture with raw ioctls and mmap streaming.
//
// State machine: open -> QUERYCAP (capture + streaming) -> ENUM_FMT -> S_FMT (read back with its
// stride) -> S_PARM (frame rate) -> exposure controls (manual exposure, auto-priority off, so the
// frame rate holds) -> REQBUFS 4 -> QUERYBUF + mmap each -> QBUF all -> STREAMON -> loop { poll
// with a timeout -> DQBUF -> convert -> QBUF } -> STREAMOFF -> munmap -> close.
// GREY and YUYV give their luma directly, MJPEG is decoded to grey. Dropped frames are counted
// from gaps in the driver's sequence numbers; timestamps come from the buffer when flagged
// monotonic. ENODEV / EIO (camera unplugged) or a stalled stream start a reconnect loop with
// exponential back-off; EBUSY names the device.
// Every system call goes through V4l2Syscalls, so tests can drive the whole state machine with a
// scripted fake device (this machine has no /dev/video*).
#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <poll.h>
#include <sys/types.h>

#include "capture/frame_source.hpp"

namespace gt::eyetrack {

// The system calls V4L2 capture makes; each returns -1 and sets errno on failure, like libc's.
struct V4l2Syscalls {
    std::function<int(const char* path, int flags)> open;
    std::function<int(int fd)> close;
    std::function<int(int fd, unsigned long request, void* arg)> ioctl;
    std::function<void*(std::size_t length, int fd, off_t offset)> mmap; // shared, read-write
    std::function<int(void* start, std::size_t length)> munmap;
    std::function<int(pollfd* fds, nfds_t n, int timeoutMs)> poll;
    std::function<void(std::chrono::milliseconds)> sleep; // reconnect back-off
    std::function<double()> nowMs;                        // CLOCK_MONOTONIC, ms

    [[nodiscard]] static V4l2Syscalls system();
};

class V4l2Source final : public FrameSource {
public:
    V4l2Source(V4l2Config config, V4l2Syscalls sys);
    ~V4l2Source() override;
    V4l2Source(const V4l2Source&) = delete;
    V4l2Source& operator=(const V4l2Source&) = delete;

    std::optional<Frame> next() override;
    std::string describe() const override { return "v4l2:" + mConfig.device; }
    std::uint64_t droppedFrames() const override { return mDropped; }
    bool liveClock() const override { return true; }

    [[nodiscard]] int width() const { return mWidth; }
    [[nodiscard]] int height() const { return mHeight; }
    [[nodiscard]] std::uint32_t pixelFormat() const { return mPixelFormat; }
    [[nodiscard]] int reconnects() const { return mReconnects; }
    [[nodiscard]] std::uint64_t corruptFrames() const { return mCorrupt; }

private:
    struct Mapping {
        void* start = nullptr;
        std::size_t length = 0;
    };

    void start();             // open .. STREAMON; throws CaptureError
    void teardown() noexcept; // STREAMOFF, munmap, close; safe to call in any state
    void reconnect(const std::string& why);
    [[nodiscard]] int xioctl(unsigned long request, void* arg) const;
    [[nodiscard]] std::string fail(const std::string& what, int err) const;
    [[nodiscard]] bool convert(const Mapping& m, std::size_t bytesUsed, cv::Mat& grey);

    V4l2Config mConfig;
    V4l2Syscalls mSys;
    int mFd = -1;
    bool mStreaming = false;
    std::vector<Mapping> mBuffers;
    int mWidth = 0, mHeight = 0;
    std::uint32_t mPixelFormat = 0, mBytesPerLine = 0, mSizeImage = 0;
    bool mHaveSequence = false;
    std::uint32_t mLastDriverSequence = 0;
    std::uint64_t mSequence = 0, mDropped = 0, mCorrupt = 0;
    int mReconnects = 0;
};

} // namespace gt::eyetrack
