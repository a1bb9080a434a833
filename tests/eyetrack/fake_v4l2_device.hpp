#pragma once
// A scripted V4L2 camera for driving V4l2Source's whole state machine without hardware:
// formats, buffers in ordinary memory, and per-frame events (EAGAIN wake-ups, short buffers,
// sequence gaps, ENODEV mid-stream, EBUSY at open).
#include <cerrno>
#include <cstring>
#include <deque>
#include <vector>

#include <linux/videodev2.h>
#include <sys/mman.h>

#include "capture/v4l2_source.hpp"

namespace gt::test {

struct FakeFrame {
    std::vector<unsigned char> bytes; // what the driver writes into the buffer
    std::uint32_t sequence = 0;
    int eagainBefore = 0;      // DQBUF answers EAGAIN this many times first
    bool unplugBefore = false; // DQBUF fails with ENODEV instead of delivering (once)
    bool monotonic = true;
    double tMs = 0.0;
};

class FakeV4l2Device {
public:
    std::vector<std::uint32_t> formats{V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_MJPEG};
    std::uint32_t width = 64, height = 48, padding = 16; // bytesperline = width * bpp + padding
    std::deque<FakeFrame> frames;
    int openErrno = 0;            // open fails with this
    int failOpensAfterUnplug = 0; // reopen attempts that fail with ENOENT after an unplug
    bool hasExposureControls = true;

    // What the source did, for the assertions.
    int opens = 0, closes = 0, streamOns = 0, streamOffs = 0, maps = 0, unmaps = 0, sleeps = 0;
    std::uint32_t chosenFormat = 0;
    std::vector<std::pair<std::uint32_t, std::int32_t>> controls;
    std::uint32_t timePerFrameDen = 0;

    [[nodiscard]] std::uint32_t bytesPerLine() const {
        return width * (chosenFormat == V4L2_PIX_FMT_YUYV ? 2u : 1u) + padding;
    }

    eyetrack::V4l2Syscalls syscalls() {
        eyetrack::V4l2Syscalls s;
        s.open = [this](const char*, int) {
            ++opens;
            if (openErrno) return fail(openErrno);
            if (mUnplugged && failOpensAfterUnplug > 0) {
                --failOpensAfterUnplug;
                return fail(ENOENT);
            }
            mUnplugged = false;
            return 7;
        };
        s.close = [this](int) {
            ++closes;
            return 0;
        };
        s.ioctl = [this](int, unsigned long request, void* arg) { return ioctl(request, arg); };
        s.mmap = [this](std::size_t length, int, off_t offset) -> void* {
            ++maps;
            auto& b = mBuffers.at(static_cast<std::size_t>(offset) / 4096);
            b.assign(length, 0);
            return b.data();
        };
        s.munmap = [this](void*, std::size_t) {
            ++unmaps;
            return 0;
        };
        s.poll = [this](pollfd* fds, nfds_t, int) {
            fds[0].revents = POLLIN;
            return frames.empty() ? 0 : 1; // nothing left: a timeout
        };
        s.sleep = [this](std::chrono::milliseconds) { ++sleeps; };
        s.nowMs = [] { return 12345.0; };
        return s;
    }

private:
    static int fail(int e) {
        errno = e;
        return -1;
    }

    int ioctl(unsigned long request, void* arg) {
        switch (request) {
        case VIDIOC_QUERYCAP: {
            auto* cap = static_cast<v4l2_capability*>(arg);
            std::memset(cap, 0, sizeof(*cap));
            cap->capabilities = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING;
            return 0;
        }
        case VIDIOC_ENUM_FMT: {
            auto* d = static_cast<v4l2_fmtdesc*>(arg);
            if (d->index >= formats.size()) return fail(EINVAL);
            d->pixelformat = formats[d->index];
            return 0;
        }
        case VIDIOC_G_FMT:
        case VIDIOC_S_FMT: {
            auto* f = static_cast<v4l2_format*>(arg);
            if (request == VIDIOC_S_FMT) chosenFormat = f->fmt.pix.pixelformat;
            f->fmt.pix.width = width;
            f->fmt.pix.height = height;
            f->fmt.pix.bytesperline = bytesPerLine();
            f->fmt.pix.sizeimage = bytesPerLine() * height;
            if (request == VIDIOC_G_FMT) f->fmt.pix.pixelformat = formats.front();
            return 0;
        }
        case VIDIOC_S_PARM:
            timePerFrameDen =
                static_cast<v4l2_streamparm*>(arg)->parm.capture.timeperframe.denominator;
            return 0;
        case VIDIOC_QUERYCTRL:
            return hasExposureControls ? 0 : fail(EINVAL);
        case VIDIOC_S_CTRL: {
            const auto* c = static_cast<v4l2_control*>(arg);
            controls.emplace_back(c->id, c->value);
            return 0;
        }
        case VIDIOC_REQBUFS:
            mBuffers.assign(static_cast<v4l2_requestbuffers*>(arg)->count, {});
            return 0;
        case VIDIOC_QUERYBUF: {
            auto* b = static_cast<v4l2_buffer*>(arg);
            b->length = bytesPerLine() * height + 4096;
            b->m.offset = b->index * 4096;
            return 0;
        }
        case VIDIOC_QBUF:
            mQueued.push_back(static_cast<v4l2_buffer*>(arg)->index);
            return 0;
        case VIDIOC_STREAMON:
            ++streamOns;
            return 0;
        case VIDIOC_STREAMOFF:
            ++streamOffs;
            mQueued.clear();
            return 0;
        case VIDIOC_DQBUF: {
            if (frames.empty()) return fail(EAGAIN);
            FakeFrame& f = frames.front();
            if (f.eagainBefore > 0) {
                --f.eagainBefore;
                return fail(EAGAIN);
            }
            if (f.unplugBefore) {
                f.unplugBefore = false;
                mUnplugged = true;
                return fail(ENODEV);
            }
            auto* b = static_cast<v4l2_buffer*>(arg);
            b->index = mQueued.front();
            mQueued.erase(mQueued.begin());
            auto& mem = mBuffers.at(b->index);
            std::memcpy(mem.data(), f.bytes.data(), std::min(mem.size(), f.bytes.size()));
            b->bytesused = static_cast<std::uint32_t>(f.bytes.size());
            b->sequence = f.sequence;
            b->flags = f.monotonic ? V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC : 0;
            b->timestamp.tv_sec = static_cast<time_t>(f.tMs / 1000.0);
            b->timestamp.tv_usec = static_cast<suseconds_t>(
                (f.tMs - 1000.0 * static_cast<double>(b->timestamp.tv_sec)) * 1000.0);
            frames.pop_front();
            return 0;
        }
        default:
            return fail(ENOTTY);
        }
    }

    std::vector<std::vector<unsigned char>> mBuffers;
    std::vector<std::uint32_t> mQueued;
    bool mUnplugged = false;
};

} // namespace gt::test
