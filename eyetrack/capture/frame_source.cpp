#include "capture/frame_source.hpp"

#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <opencv2/imgproc.hpp>

#include "capture/file_sources.hpp"
#include "capture/v4l2_source.hpp"
#include "error.hpp"

namespace gt::eyetrack {

cv::Mat toGrey(const cv::Mat& image) {
    cv::Mat m = image;
    if (m.depth() == CV_16U)
        m.convertTo(m, CV_8U, 1.0 / 257.0);
    else if (m.depth() != CV_8U)
        throw CaptureError("frame has an unsupported pixel depth");
    cv::Mat grey;
    switch (m.channels()) {
    case 1:
        grey = m.clone();
        break;
    case 3:
        cv::cvtColor(m, grey, cv::COLOR_BGR2GRAY);
        break;
    case 4:
        cv::cvtColor(m, grey, cv::COLOR_BGRA2GRAY);
        break;
    default:
        throw CaptureError("frame has an unsupported number of channels");
    }
    return grey;
}

namespace {

// A camera is the one input that is not a regular file: a V4L2 device, a character device with
// the video major number (81, as Linux numbers /dev/videoN and v4l2loopback alike). Anything else
// (a FIFO, a regular file, /dev/zero) is refused before it is opened: a FIFO would otherwise be
// opened read-write and fail only at the first ioctl.
void checkCameraDevice(const std::string& device) {
    constexpr unsigned kVideoMajor = 81;
    struct stat st {};
    if (::stat(device.c_str(), &st) != 0) return; // V4l2Source names the missing camera
    if (S_ISCHR(st.st_mode) && major(st.st_rdev) == kVideoMajor) return;
    const std::string kind = S_ISCHR(st.st_mode)    ? "a character device that is not a camera"
                             : S_ISFIFO(st.st_mode) ? "a FIFO"
                             : S_ISDIR(st.st_mode)  ? "a folder"
                             : S_ISREG(st.st_mode)  ? "a regular file"
                                                    : "not a device";
    throw CaptureError("v4l2 " + device + ": " + kind + ", not a V4L2 capture device");
}

} // namespace

std::unique_ptr<FrameSource> openFrameSource(const FrameSourceConfig& config) {
    struct Opener {
        std::unique_ptr<FrameSource> operator()(const V4l2Config& c) const {
            checkCameraDevice(c.device);
            return std::make_unique<V4l2Source>(c, V4l2Syscalls::system());
        }
        std::unique_ptr<FrameSource> operator()(const VideoFileConfig& c) const {
            return std::make_unique<VideoFileSource>(c.path);
        }
        std::unique_ptr<FrameSource> operator()(const ImageFolderConfig& c) const {
            return std::make_unique<ImageFolderSource>(c.folder, c.fps);
        }
        std::unique_ptr<FrameSource> operator()(const EyeSimConfig& c) const {
            return std::make_unique<SyntheticSource>(c);
        }
    };
    return std::visit(Opener{}, config);
}

} // namespace gt::eyetrack
