#pragma once
// What openFrameSource() opens, as typed values: one config per kind of source. The command line's
// spelling of these (v4l2:DEVICE?fps=.., video:FILE, ..) is the application's to parse.
#include <chrono>
#include <string>
#include <variant>

#include "sim/synthetic_eye.hpp"

namespace gt::eyetrack {

// The pixel formats V4L2 capture converts to grey.
enum class V4l2PixelFormat {
    FirstOffered, // the first the camera offers of GREY, YUYV, MJPEG, in that order
    Grey,
    Yuyv,
    Mjpeg,
};

// A V4L2 camera.
struct V4l2Config {
    std::string device = "/dev/video0";
    int width = 0, height = 0; // 0: keep the driver's current size
    double fps = 0.0;          // 0: keep the driver's rate
    V4l2PixelFormat format = V4l2PixelFormat::FirstOffered;
    int pollTimeoutMs = 1000;
    int reconnectAttempts = 8;
    std::chrono::milliseconds backoffStart{100};
    std::chrono::milliseconds backoffMax{2000};
};

// A video file (OpenCV VideoCapture; timestamps from the file).
struct VideoFileConfig {
    std::string path;
};

// Sorted image files in a folder, timestamped at a fixed rate.
struct ImageFolderConfig {
    std::string folder;
    double fps = 30.0;
};

// gazetrace's synthetic eye is configured by its EyeSimConfig.
using FrameSourceConfig =
    std::variant<V4l2Config, VideoFileConfig, ImageFolderConfig, EyeSimConfig>;

} // namespace gt::eyetrack
