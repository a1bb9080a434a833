#pragma once
// Recorded frame sources: video files, image folders and the synthetic eye.
#include <filesystem>
#include <memory>
#include <string_view>
#include <vector>

#include <opencv2/videoio.hpp>

#include "capture/frame_source.hpp"
#include "sim/synthetic_eye.hpp"

namespace gt::eyetrack {

// A video file's container, recognised by its first bytes. A Playlist is text that names other
// inputs (HLS, M3U, ffconcat, SDP...): refused, whatever the file's extension.
enum class VideoContainer { Avi, Matroska, Mp4, Playlist, Unknown };
[[nodiscard]] VideoContainer sniffVideoContainer(std::string_view head);

// An open file descriptor, closed when it goes.
class UniqueFd {
public:
    explicit UniqueFd(int fd = -1) noexcept : mFd(fd) {}
    ~UniqueFd();
    UniqueFd(const UniqueFd&) = delete;
    UniqueFd& operator=(const UniqueFd&) = delete;
    [[nodiscard]] int get() const noexcept { return mFd; }

private:
    int mFd;
};

class VideoFileSource final : public FrameSource {
public:
    explicit VideoFileSource(const std::filesystem::path& file);
    std::optional<Frame> next() override;
    std::string describe() const override { return "video:" + mFile.string(); }

private:
    std::filesystem::path mFile;
    UniqueFd mFd; // the checked file, which FFmpeg reads through /proc/self/fd
    VideoContainer mContainer = VideoContainer::Unknown;
    cv::VideoCapture mCapture;
    double mFps = 0.0;
    std::int64_t mExpected = 0; // frame count from the container, 0 if unknown
    std::uint64_t mNext = 0;
};

class ImageFolderSource final : public FrameSource {
public:
    ImageFolderSource(const std::filesystem::path& dir, double fps);
    std::optional<Frame> next() override;
    std::string describe() const override { return "images:" + mDir.string(); }

private:
    std::filesystem::path mDir;
    std::vector<std::filesystem::path> mFiles;
    double mFps;
    std::size_t mNext = 0;
    cv::Size mFrameSize; // the first frame's: every frame of one camera has it
};

class SyntheticSource final : public FrameSource {
public:
    explicit SyntheticSource(EyeSimConfig config);
    std::optional<Frame> next() override;
    std::string describe() const override;
    [[nodiscard]] const SyntheticEye& eye() const { return mEye; }

private:
    SyntheticEye mEye;
    int mNext = 0;
};

} // namespace gt::eyetrack
