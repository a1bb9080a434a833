#include "capture/v4l2_source.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <iostream>
#include <thread>

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <opencv2/imgcodecs.hpp>

#include "error.hpp"

namespace gt::eyetrack {

namespace {

constexpr std::uint32_t kBufferCount = 4;

std::string fourcc(std::uint32_t f) {
    std::string s(4, ' ');
    for (int i = 0; i < 4; ++i)
        s[static_cast<std::size_t>(i)] = static_cast<char>((f >> (8 * i)) & 0xff);
    return s;
}

// The V4L2 code of a format asked for; 0 for the first offered.
std::uint32_t pixelFormatCode(V4l2PixelFormat format) {
    switch (format) {
    case V4l2PixelFormat::Grey:
        return V4L2_PIX_FMT_GREY;
    case V4l2PixelFormat::Yuyv:
        return V4L2_PIX_FMT_YUYV;
    case V4l2PixelFormat::Mjpeg:
        return V4L2_PIX_FMT_MJPEG;
    case V4l2PixelFormat::FirstOffered:
        break;
    }
    return 0;
}

} // namespace

V4l2Syscalls V4l2Syscalls::system() {
    V4l2Syscalls s;
    s.open = [](const char* path, int flags) { return ::open(path, flags); };
    s.close = [](int fd) { return ::close(fd); };
    s.ioctl = [](int fd, unsigned long request, void* arg) { return ::ioctl(fd, request, arg); };
    s.mmap = [](std::size_t length, int fd, off_t offset) {
        return ::mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, offset);
    };
    s.munmap = [](void* start, std::size_t length) { return ::munmap(start, length); };
    s.poll = [](pollfd* fds, nfds_t n, int timeoutMs) { return ::poll(fds, n, timeoutMs); };
    s.sleep = [](std::chrono::milliseconds d) { std::this_thread::sleep_for(d); };
    s.nowMs = [] {
        timespec ts{};
        clock_gettime(CLOCK_MONOTONIC, &ts);
        return static_cast<double>(ts.tv_sec) * 1000.0 + static_cast<double>(ts.tv_nsec) / 1e6;
    };
    return s;
}

V4l2Source::V4l2Source(V4l2Config config, V4l2Syscalls sys)
    : mConfig(std::move(config)), mSys(std::move(sys)) {
    try {
        start();
    } catch (...) {
        teardown();
        throw;
    }
}

V4l2Source::~V4l2Source() {
    teardown();
}

int V4l2Source::xioctl(unsigned long request, void* arg) const {
    int r = 0;
    do {
        r = mSys.ioctl(mFd, request, arg);
    } while (r == -1 && errno == EINTR);
    return r;
}

std::string V4l2Source::fail(const std::string& what, int err) const {
    return "v4l2 " + mConfig.device + ": " + what + " failed: " + std::strerror(err);
}

void V4l2Source::start() {
    mFd = mSys.open(mConfig.device.c_str(), O_RDWR | O_NONBLOCK);
    if (mFd < 0) {
        const int e = errno;
        if (e == ENOENT || e == ENODEV || e == ENXIO)
            throw CaptureError("v4l2 " + mConfig.device + ": no such camera");
        if (e == EBUSY)
            throw CaptureError("v4l2 " + mConfig.device +
                               ": camera is busy (in use by another program)");
        if (e == EACCES)
            throw CaptureError("v4l2 " + mConfig.device +
                               ": permission denied (is the user in the 'video' group?)");
        throw CaptureError(fail("open", e));
    }
    v4l2_capability cap{};
    if (xioctl(VIDIOC_QUERYCAP, &cap) < 0) {
        const int e = errno;
        throw CaptureError(e == ENOTTY ? "v4l2 " + mConfig.device + ": not a V4L2 device"
                                       : fail("VIDIOC_QUERYCAP", e));
    }
    const std::uint32_t caps =
        (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
    if (!(caps & V4L2_CAP_VIDEO_CAPTURE) || !(caps & V4L2_CAP_STREAMING))
        throw CaptureError("v4l2 " + mConfig.device +
                           ": not a video capture device with streaming I/O");

    std::vector<std::uint32_t> offered;
    for (std::uint32_t i = 0;; ++i) {
        v4l2_fmtdesc desc{};
        desc.index = i;
        desc.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        if (xioctl(VIDIOC_ENUM_FMT, &desc) < 0) break; // EINVAL ends the list
        offered.push_back(desc.pixelformat);
    }
    auto has = [&](std::uint32_t f) {
        return std::find(offered.begin(), offered.end(), f) != offered.end();
    };
    std::uint32_t want = pixelFormatCode(mConfig.format);
    if (want == 0) {
        for (std::uint32_t f : {V4L2_PIX_FMT_GREY, V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_MJPEG})
            if (want == 0 && has(f)) want = f;
    }
    if (want == 0 || !has(want)) {
        std::string list;
        for (std::uint32_t f : offered)
            list += (list.empty() ? "" : ", ") + fourcc(f);
        throw CaptureError("v4l2 " + mConfig.device + ": no usable format (want " +
                           (want ? fourcc(want) : std::string("GREY, YUYV or MJPG")) + "; offers " +
                           (list.empty() ? std::string("none") : list) + ")");
    }

    v4l2_format fmt{};
    fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(VIDIOC_G_FMT, &fmt) < 0) throw CaptureError(fail("VIDIOC_G_FMT", errno));
    if (mConfig.width > 0) fmt.fmt.pix.width = static_cast<std::uint32_t>(mConfig.width);
    if (mConfig.height > 0) fmt.fmt.pix.height = static_cast<std::uint32_t>(mConfig.height);
    fmt.fmt.pix.pixelformat = want;
    fmt.fmt.pix.field = V4L2_FIELD_ANY;
    if (xioctl(VIDIOC_S_FMT, &fmt) < 0) {
        const int e = errno;
        throw CaptureError(e == EBUSY ? "v4l2 " + mConfig.device +
                                            ": camera is busy (in use by another program)"
                                      : fail("VIDIOC_S_FMT", e));
    }
    // The driver may adjust everything: read back what it chose, stride included.
    if (fmt.fmt.pix.pixelformat != want)
        throw CaptureError("v4l2 " + mConfig.device + ": driver replaced " + fourcc(want) +
                           " with " + fourcc(fmt.fmt.pix.pixelformat));
    mPixelFormat = want;
    mWidth = static_cast<int>(fmt.fmt.pix.width);
    mHeight = static_cast<int>(fmt.fmt.pix.height);
    const std::uint32_t bpp = want == V4L2_PIX_FMT_YUYV ? 2 : 1;
    mBytesPerLine = std::max(fmt.fmt.pix.bytesperline, fmt.fmt.pix.width * bpp);
    mSizeImage = fmt.fmt.pix.sizeimage;
    if (mWidth <= 0 || mHeight <= 0)
        throw CaptureError("v4l2 " + mConfig.device + ": driver reported an empty frame size");

    if (mConfig.fps > 0.0) {
        v4l2_streamparm parm{};
        parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        parm.parm.capture.timeperframe.numerator = 1000;
        parm.parm.capture.timeperframe.denominator =
            static_cast<std::uint32_t>(mConfig.fps * 1000.0 + 0.5);
        if (xioctl(VIDIOC_S_PARM, &parm) < 0)
            std::cerr << "gazetrace: warning: v4l2 " << mConfig.device << ": cannot set "
                      << mConfig.fps << " fps\n";
    }
    // Manual exposure and no auto-priority: with auto exposure many cameras lower the frame rate
    // in dim light, which would change the tracker's timing under the user.
    auto setControl = [&](std::uint32_t id, std::int32_t value) {
        v4l2_queryctrl q{};
        q.id = id;
        if (xioctl(VIDIOC_QUERYCTRL, &q) < 0 || (q.flags & V4L2_CTRL_FLAG_DISABLED))
            return; // not offered
        v4l2_control ctl{};
        ctl.id = id;
        ctl.value = value;
        (void)xioctl(VIDIOC_S_CTRL, &ctl);
    };
    setControl(V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_MANUAL);
    setControl(V4L2_CID_EXPOSURE_AUTO_PRIORITY, 0);

    v4l2_requestbuffers req{};
    req.count = kBufferCount;
    req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    req.memory = V4L2_MEMORY_MMAP;
    if (xioctl(VIDIOC_REQBUFS, &req) < 0) {
        const int e = errno;
        throw CaptureError(e == EBUSY ? "v4l2 " + mConfig.device +
                                            ": camera is busy (in use by another program)"
                                      : fail("VIDIOC_REQBUFS", e));
    }
    if (req.count < 2)
        throw CaptureError("v4l2 " + mConfig.device + ": driver granted only " +
                           std::to_string(req.count) + " buffer(s)");
    for (std::uint32_t i = 0; i < req.count; ++i) {
        v4l2_buffer buf{};
        buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        buf.memory = V4L2_MEMORY_MMAP;
        buf.index = i;
        if (xioctl(VIDIOC_QUERYBUF, &buf) < 0) throw CaptureError(fail("VIDIOC_QUERYBUF", errno));
        void* start = mSys.mmap(buf.length, mFd, static_cast<off_t>(buf.m.offset));
        if (start == MAP_FAILED) throw CaptureError(fail("mmap", errno));
        mBuffers.push_back({start, buf.length});
    }
    for (std::uint32_t i = 0; i < mBuffers.size(); ++i) {
        v4l2_buffer buf{};
        buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        buf.memory = V4L2_MEMORY_MMAP;
        buf.index = i;
        if (xioctl(VIDIOC_QBUF, &buf) < 0) throw CaptureError(fail("VIDIOC_QBUF", errno));
    }
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(VIDIOC_STREAMON, &type) < 0) throw CaptureError(fail("VIDIOC_STREAMON", errno));
    mStreaming = true;
    mHaveSequence = false;
}

void V4l2Source::teardown() noexcept {
    if (mFd >= 0 && mStreaming) {
        int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        (void)xioctl(VIDIOC_STREAMOFF, &type);
    }
    mStreaming = false;
    for (const Mapping& m : mBuffers)
        (void)mSys.munmap(m.start, m.length);
    mBuffers.clear();
    if (mFd >= 0) (void)mSys.close(mFd);
    mFd = -1;
}

void V4l2Source::reconnect(const std::string& why) {
    std::cerr << "gazetrace: warning: v4l2 " << mConfig.device << ": " << why << "; reconnecting\n";
    teardown();
    std::chrono::milliseconds wait = mConfig.backoffStart;
    std::string last;
    for (int attempt = 1; attempt <= mConfig.reconnectAttempts; ++attempt) {
        mSys.sleep(wait);
        try {
            start();
            ++mReconnects;
            return;
        } catch (const CaptureError& e) {
            last = e.what();
            teardown();
        }
        wait = std::min(mConfig.backoffMax, wait * 2);
    }
    throw CaptureError("v4l2 " + mConfig.device + ": " + why + ", and it did not come back after " +
                       std::to_string(mConfig.reconnectAttempts) + " attempts (" + last + ")");
}

bool V4l2Source::convert(const Mapping& m, std::size_t bytesUsed, cv::Mat& grey) {
    const auto* data = static_cast<const unsigned char*>(m.start);
    if (mPixelFormat == V4L2_PIX_FMT_MJPEG) {
        if (bytesUsed == 0 || bytesUsed > m.length) return false;
        const cv::Mat encoded(1, static_cast<int>(bytesUsed), CV_8U,
                              const_cast<unsigned char*>(data));
        grey = cv::imdecode(encoded, cv::IMREAD_GRAYSCALE);
        return !grey.empty() && grey.cols == mWidth && grey.rows == mHeight;
    }
    // GREY and YUYV: a short buffer (the driver delivered less than a frame) is dropped.
    const std::size_t need =
        static_cast<std::size_t>(mBytesPerLine) * static_cast<std::size_t>(mHeight - 1) +
        static_cast<std::size_t>(mWidth) * (mPixelFormat == V4L2_PIX_FMT_YUYV ? 2u : 1u);
    if (bytesUsed < need || need > m.length) return false;
    grey.create(mHeight, mWidth, CV_8U);
    for (int y = 0; y < mHeight; ++y) {
        const unsigned char* row = data + static_cast<std::size_t>(y) * mBytesPerLine;
        unsigned char* out = grey.ptr<unsigned char>(y);
        if (mPixelFormat == V4L2_PIX_FMT_GREY) {
            std::memcpy(out, row, static_cast<std::size_t>(mWidth));
        } else {
            for (int x = 0; x < mWidth; ++x)
                out[x] = row[2 * x]; // Y0 U Y1 V: luma at even bytes
        }
    }
    return true;
}

std::optional<Frame> V4l2Source::next() {
    for (;;) {
        pollfd pfd{mFd, POLLIN, 0};
        const int ready = mSys.poll(&pfd, 1, mConfig.pollTimeoutMs);
        if (ready < 0) {
            if (errno == EINTR) continue;
            reconnect(fail("poll", errno));
            continue;
        }
        if (ready == 0) {
            reconnect("no frame within " + std::to_string(mConfig.pollTimeoutMs) + " ms");
            continue;
        }
        if (pfd.revents & (POLLERR | POLLHUP | POLLNVAL)) {
            reconnect("camera lost (poll reported an error)");
            continue;
        }
        v4l2_buffer buf{};
        buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        buf.memory = V4L2_MEMORY_MMAP;
        if (xioctl(VIDIOC_DQBUF, &buf) < 0) {
            const int e = errno;
            if (e == EAGAIN) continue; // woke without a frame: poll again
            if (e == ENODEV || e == EIO) {
                reconnect(std::string("camera lost (") + std::strerror(e) + ")");
                continue;
            }
            throw CaptureError(fail("VIDIOC_DQBUF", e));
        }
        if (buf.index >= mBuffers.size())
            throw CaptureError("v4l2 " + mConfig.device + ": driver returned buffer " +
                               std::to_string(buf.index) + " of " +
                               std::to_string(mBuffers.size()));

        Frame f;
        const bool ok = !(buf.flags & V4L2_BUF_FLAG_ERROR) &&
                        convert(mBuffers[buf.index], buf.bytesused, f.grey);
        if ((buf.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC)
            f.tMs = static_cast<double>(buf.timestamp.tv_sec) * 1000.0 +
                    static_cast<double>(buf.timestamp.tv_usec) / 1000.0;
        else
            f.tMs = mSys.nowMs();
        f.arrival = std::chrono::steady_clock::now();
        // Gaps in the driver's sequence numbers are frames the driver dropped.
        if (mHaveSequence && buf.sequence > mLastDriverSequence + 1) {
            mDropped += buf.sequence - mLastDriverSequence - 1;
            mSequence += buf.sequence - mLastDriverSequence - 1;
        }
        mHaveSequence = true;
        mLastDriverSequence = buf.sequence;
        if (xioctl(VIDIOC_QBUF, &buf) < 0) {
            const int e = errno;
            if (e == ENODEV || e == EIO) {
                reconnect(std::string("camera lost (") + std::strerror(e) + ")");
                continue;
            }
            throw CaptureError(fail("VIDIOC_QBUF", e));
        }
        if (!ok) {
            ++mCorrupt; // short or undecodable buffer: skipped, counted
            ++mDropped;
            ++mSequence;
            continue;
        }
        f.sequence = mSequence++;
        return f;
    }
}

} // namespace gt::eyetrack
