#include "capture/file_sources.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio/registry.hpp>

#include "error.hpp"

namespace gt::eyetrack {

VideoFileSource::VideoFileSource(const std::filesystem::path& file) : mFile(file) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec))
        throw CaptureError("video " + file.string() + ": no such file");
    if (!std::filesystem::is_regular_file(file, ec)) {
        // /dev/null, a folder, a pipe: there, but not a video file ("no such file").
        throw CaptureError("video " + file.string() + ": not a regular file");
    }
    if (std::filesystem::file_size(file, ec) == 0)
        throw CaptureError("video " + file.string() + ": file is empty");
    // FFmpeg would print its own lines about damaged files; the error we raise says it in one.
    // (Read by OpenCV's FFmpeg backend when it loads; a value the user set is kept.)
    ::setenv("OPENCV_FFMPEG_LOGLEVEL", "-8", 0);
    // Only FFmpeg, probed first: letting OpenCV fall back to any backend made GStreamer and the
    // image-sequence reader try an unreadable file and print four lines of their own before
    // ours. OpenCV's own log is quiet while it opens.
    if (!cv::videoio_registry::hasBackend(cv::CAP_FFMPEG)) {
        throw CaptureError("video " + file.string() +
                           ": this OpenCV has no FFmpeg video backend (install libopencv-dev "
                           "from Debian, which has it)");
    }
    const auto level = cv::utils::logging::getLogLevel();
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
    const bool opened = mCapture.open(file.string(), cv::CAP_FFMPEG);
    cv::utils::logging::setLogLevel(level);
    if (!opened)
        throw CaptureError("video " + file.string() +
                           ": cannot be decoded (not a video, or truncated)");
    mFps = mCapture.get(cv::CAP_PROP_FPS);
    mExpected = static_cast<std::int64_t>(mCapture.get(cv::CAP_PROP_FRAME_COUNT));
}

std::optional<Frame> VideoFileSource::next() {
    cv::Mat image;
    if (!mCapture.read(image) || image.empty()) {
        if (mNext == 0)
            throw CaptureError("video " + mFile.string() +
                               ": no decodable frame (empty or truncated file)");
        // Containers report their frame count from the header; noticeably fewer decoded frames
        // means the file was cut short. (Counts from some containers are estimates: allow 2 %.)
        if (mExpected > 0 &&
            static_cast<double>(mNext) < 0.98 * static_cast<double>(mExpected) - 1.0)
            throw CaptureError("video " + mFile.string() + ": truncated after frame " +
                               std::to_string(mNext) + " of " + std::to_string(mExpected));
        return std::nullopt;
    }
    Frame f;
    f.grey = toGrey(image);
    f.sequence = mNext;
    // The file's frame rate places each frame exactly (container timestamps are often rounded to
    // whole milliseconds); without one, the decoder's position of this frame.
    f.tMs = mFps > 0.0 ? static_cast<double>(mNext) * 1000.0 / mFps
                       : mCapture.get(cv::CAP_PROP_POS_MSEC);
    f.arrival = std::chrono::steady_clock::now();
    ++mNext;
    return f;
}

ImageFolderSource::ImageFolderSource(const std::filesystem::path& dir, double fps)
    : mDir(dir), mFps(fps) {
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec))
        throw CaptureError("images " + dir.string() + ": no such folder");
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
        std::string ext = entry.path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(),
                       [](unsigned char ch) { return std::tolower(ch); });
        if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".pgm" || ext == ".bmp" ||
            ext == ".tif" || ext == ".tiff")
            mFiles.push_back(entry.path());
    }
    if (mFiles.empty())
        throw CaptureError("images " + dir.string() + ": no image files (png, jpg, pgm, bmp, tif)");
    std::sort(mFiles.begin(), mFiles.end());
}

std::optional<Frame> ImageFolderSource::next() {
    if (mNext >= mFiles.size()) return std::nullopt;
    const cv::Mat image = cv::imread(mFiles[mNext].string(), cv::IMREAD_UNCHANGED);
    if (image.empty())
        throw CaptureError("images: " + mFiles[mNext].string() + " cannot be decoded (after " +
                           std::to_string(mNext) + " good frames)");
    Frame f;
    f.grey = toGrey(image);
    f.sequence = mNext;
    f.tMs = static_cast<double>(mNext) * 1000.0 / mFps;
    f.arrival = std::chrono::steady_clock::now();
    ++mNext;
    return f;
}

SyntheticSource::SyntheticSource(EyeSimConfig config) : mEye(std::move(config)) {}

std::optional<Frame> SyntheticSource::next() {
    if (mNext >= mEye.config().frames) return std::nullopt;
    Frame f;
    f.grey = mEye.render(mNext);
    f.sequence = static_cast<std::uint64_t>(mNext);
    f.tMs = mEye.frameTimeMs(mNext);
    f.arrival = std::chrono::steady_clock::now();
    ++mNext;
    return f;
}

std::string SyntheticSource::describe() const {
    return "synthetic:" + std::to_string(mEye.config().seed);
}

} // namespace gt::eyetrack
