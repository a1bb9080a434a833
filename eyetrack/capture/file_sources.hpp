#pragma once
// Recorded frame sources: video files, image folders and the synthetic eye.
#include <filesystem>
#include <memory>
#include <vector>

#include <opencv2/videoio.hpp>

#include "capture/frame_source.hpp"
#include "sim/synthetic_eye.hpp"

namespace gt::eyetrack {

class VideoFileSource final : public FrameSource {
public:
    explicit VideoFileSource(const std::filesystem::path& file);
    std::optional<Frame> next() override;
    std::string describe() const override { return "video:" + mFile.string(); }

private:
    std::filesystem::path mFile;
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
