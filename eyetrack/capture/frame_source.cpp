#include "capture/frame_source.hpp"

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

std::unique_ptr<FrameSource> openFrameSource(const FrameSourceConfig& config) {
    struct Opener {
        std::unique_ptr<FrameSource> operator()(const V4l2Config& c) const {
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
