// V4l2Source's state machine against a scripted fake camera (this machine has no /dev/video*).
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "capture/v4l2_source.hpp"
#include "error.hpp"
#include "fake_v4l2_device.hpp"

using gt::eyetrack::CaptureError;
using gt::eyetrack::V4l2Config;
using gt::eyetrack::V4l2Source;
using gt::test::FakeFrame;
using gt::test::FakeV4l2Device;

namespace {

// A YUYV frame whose luma at (x, y) is (x + 2y + seq) & 0xff; chroma bytes are 0x80.
FakeFrame yuyvFrame(const FakeV4l2Device& d, std::uint32_t seq) {
    FakeFrame f;
    f.sequence = seq;
    f.tMs = 1000.0 + seq * 10.0;
    const std::uint32_t stride = d.width * 2 + d.padding;
    f.bytes.assign(static_cast<std::size_t>(stride) * d.height,
                   0xEE); // padding bytes must be skipped
    for (std::uint32_t y = 0; y < d.height; ++y)
        for (std::uint32_t x = 0; x < d.width; ++x) {
            f.bytes[y * stride + 2 * x] = static_cast<unsigned char>((x + 2 * y + seq) & 0xff);
            f.bytes[y * stride + 2 * x + 1] = 0x80;
        }
    return f;
}

V4l2Config config() {
    V4l2Config c;
    c.device = "/dev/video9";
    c.fps = 120.0;
    c.reconnectAttempts = 3;
    return c;
}

} // namespace

TEST(V4l2Capture, NegotiatesStreamsAndReadsLumaWithStride) {
    FakeV4l2Device dev;
    dev.frames.push_back(yuyvFrame(dev, 0));
    dev.frames.push_back(yuyvFrame(dev, 1));
    {
        V4l2Source src(config(), dev.syscalls());
        EXPECT_EQ(dev.chosenFormat, V4L2_PIX_FMT_YUYV); // no GREY offered: YUYV before MJPEG
        EXPECT_EQ(dev.maps, 4);                         // REQBUFS 4, each mapped
        EXPECT_EQ(dev.streamOns, 1);
        EXPECT_EQ(dev.timePerFrameDen, 120000u); // S_PARM 1000/120000 s
        ASSERT_EQ(dev.controls.size(), 2u);      // manual exposure, auto-priority off
        EXPECT_EQ(dev.controls[0], std::make_pair(std::uint32_t(V4L2_CID_EXPOSURE_AUTO),
                                                  std::int32_t(V4L2_EXPOSURE_MANUAL)));
        EXPECT_EQ(dev.controls[1],
                  std::make_pair(std::uint32_t(V4L2_CID_EXPOSURE_AUTO_PRIORITY), 0));
        for (std::uint32_t seq = 0; seq < 2; ++seq) {
            auto f = src.next();
            ASSERT_TRUE(f);
            ASSERT_EQ(f->grey.size(), cv::Size(64, 48));
            EXPECT_EQ(f->sequence, seq);
            EXPECT_DOUBLE_EQ(f->tMs, 1000.0 + seq * 10.0); // monotonic buffer timestamp
            for (int y = 0; y < 48; y += 7)
                for (int x = 0; x < 64; x += 5)
                    ASSERT_EQ(f->grey.at<uchar>(y, x), (x + 2 * y + static_cast<int>(seq)) & 0xff);
        }
    }
    EXPECT_EQ(dev.streamOffs, 1); // the destructor stops, unmaps and closes
    EXPECT_EQ(dev.unmaps, 4);
    EXPECT_EQ(dev.closes, 1);
}

TEST(V4l2Capture, RetriesEagainCountsGapsAndSkipsShortBuffers) {
    FakeV4l2Device dev;
    dev.frames.push_back(yuyvFrame(dev, 0));
    FakeFrame late = yuyvFrame(dev, 1);
    late.eagainBefore = 3;
    dev.frames.push_back(late);
    FakeFrame shortFrame = yuyvFrame(dev, 2);
    shortFrame.bytes.resize(100); // a short read
    dev.frames.push_back(shortFrame);
    dev.frames.push_back(yuyvFrame(dev, 6)); // driver dropped 3, 4, 5
    V4l2Source src(config(), dev.syscalls());
    EXPECT_EQ(src.next()->sequence, 0u);
    EXPECT_EQ(src.next()->sequence, 1u);
    const auto f = src.next();
    ASSERT_TRUE(f);
    EXPECT_EQ(f->sequence, 6u); // numbering keeps the gaps
    EXPECT_EQ(src.corruptFrames(), 1u);
    EXPECT_EQ(src.droppedFrames(), 4u); // 3 missing + 1 short
}

TEST(V4l2Capture, ReconnectsAfterUnplugMidStream) {
    FakeV4l2Device dev;
    dev.frames.push_back(yuyvFrame(dev, 0));
    FakeFrame after = yuyvFrame(dev, 0); // a fresh stream starts its count again
    after.unplugBefore = true;
    dev.frames.push_back(after);
    dev.failOpensAfterUnplug = 2; // the camera needs a moment to re-enumerate
    V4l2Source src(config(), dev.syscalls());
    ASSERT_TRUE(src.next());
    const auto f = src.next();
    ASSERT_TRUE(f);
    EXPECT_EQ(src.reconnects(), 1);
    EXPECT_EQ(dev.sleeps, 3); // back-off before each of the three opens
    EXPECT_EQ(dev.streamOns, 2);
    EXPECT_EQ(dev.unmaps, 4); // the old mappings were released
}

TEST(V4l2Capture, GivesUpWithAClearMessageWhenTheCameraStaysAway) {
    FakeV4l2Device dev;
    FakeFrame f = yuyvFrame(dev, 0);
    f.unplugBefore = true;
    dev.frames.push_back(f);
    dev.failOpensAfterUnplug = 100;
    V4l2Source src(config(), dev.syscalls());
    try {
        (void)src.next();
        FAIL() << "expected CaptureError";
    } catch (const CaptureError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("/dev/video9"), std::string::npos) << m;
        EXPECT_NE(m.find("did not come back after 3 attempts"), std::string::npos) << m;
    }
}

TEST(V4l2Capture, BusyMissingAndFormatlessDevicesAreNamed) {
    {
        FakeV4l2Device dev;
        dev.openErrno = EBUSY;
        EXPECT_THROW(
            {
                try {
                    V4l2Source src(config(), dev.syscalls());
                } catch (const CaptureError& e) {
                    EXPECT_STREQ(e.what(),
                                 "v4l2 /dev/video9: camera is busy (in use by another program)");
                    throw;
                }
            },
            CaptureError);
    }
    {
        FakeV4l2Device dev;
        dev.openErrno = ENOENT;
        EXPECT_THROW(V4l2Source(config(), dev.syscalls()), CaptureError);
    }
    {
        FakeV4l2Device dev;
        dev.formats = {v4l2_fourcc('R', 'G', 'B', '3')};
        try {
            V4l2Source src(config(), dev.syscalls());
            FAIL();
        } catch (const CaptureError& e) {
            EXPECT_NE(std::string(e.what()).find("offers RGB3"), std::string::npos) << e.what();
        }
        EXPECT_EQ(dev.closes, 1); // nothing leaks on a failed start
    }
}

TEST(V4l2Capture, GreyAndMjpegFormats) {
    {
        FakeV4l2Device dev;
        dev.formats = {V4L2_PIX_FMT_MJPEG, V4L2_PIX_FMT_GREY};
        FakeFrame f;
        f.bytes.assign((dev.width + dev.padding) * dev.height, 77);
        dev.frames.push_back(f);
        V4l2Source src(config(), dev.syscalls());
        EXPECT_EQ(dev.chosenFormat, V4L2_PIX_FMT_GREY);
        EXPECT_EQ(src.next()->grey.at<uchar>(10, 10), 77);
    }
    {
        FakeV4l2Device dev;
        dev.formats = {V4L2_PIX_FMT_MJPEG};
        cv::Mat img(48, 64, CV_8U, cv::Scalar(128));
        std::vector<unsigned char> jpeg;
        cv::imencode(".jpg", img, jpeg);
        FakeFrame good;
        good.bytes = jpeg;
        good.monotonic = false;
        FakeFrame broken;
        broken.bytes = {0xFF, 0xD8, 0x00};
        broken.sequence = 1;
        dev.frames.push_back(broken);
        good.sequence = 2;
        dev.frames.push_back(good);
        V4l2Source src(config(), dev.syscalls());
        const auto f = src.next();
        ASSERT_TRUE(f);
        EXPECT_NEAR(f->grey.at<uchar>(20, 20), 128, 2);
        EXPECT_DOUBLE_EQ(f->tMs, 12345.0); // no monotonic flag: the clock at dequeue
        EXPECT_EQ(src.corruptFrames(), 1u);
    }
}

TEST(V4l2Capture, MissingDeviceIsNamed) {
    V4l2Config c;
    c.device = "/dev/video_missing_for_test";
    try {
        (void)gt::eyetrack::openFrameSource(c);
        ADD_FAILURE() << "a missing device opened";
    } catch (const CaptureError& e) {
        EXPECT_NE(std::string(e.what()).find("/dev/video_missing_for_test"), std::string::npos)
            << e.what();
    }
}
