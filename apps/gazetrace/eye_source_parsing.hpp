#pragma once
// The eye tracker's command-line values turned into eyetrack's typed ones: frame sources
// (--source and friends), the gaze model (--model), the pupil detector (--detector), the eye
// regions of one camera (--regions) and where gaze is sent (--emit). Every
// error is an ArgumentError, one line naming the bad value.
//
// Frame sources:
//   v4l2:/dev/videoN[?width=..&height=..&fps=..&format=grey|yuyv|mjpeg]   a V4L2 camera
//   video:FILE        a video file (OpenCV VideoCapture; timestamps from the file)
//   images:DIR        sorted image files in a folder (timestamps at 30 frames/s)
//   synthetic:SEED[?preset=clean|hard&frames=N&size=WxH&fps=F]   gazetrace's synthetic eye
#include <map>
#include <memory>
#include <string>

#include <utility>

#include <opencv2/core/types.hpp>

#include "capture/frame_source.hpp"
#include "gaze/calibration_set.hpp"
#include "net/udp_emitter.hpp"
#include "pupil/pupil_detector.hpp"

namespace gt::app {

// "scheme:rest?key=value&..." split into its parts (video and images keep any '?' in the path).
struct SourceSpec {
    std::string scheme;
    std::string target;
    std::map<std::string, std::string> options;
};
[[nodiscard]] SourceSpec splitSourceSpec(const std::string& spec);

[[nodiscard]] eyetrack::FrameSourceConfig frameSourceConfig(const std::string& spec);
// frameSourceConfig() opened.
[[nodiscard]] std::unique_ptr<eyetrack::FrameSource> openFrameSource(const std::string& spec);

// "2d" | "3d".
[[nodiscard]] eyetrack::GazeModel gazeModel(const std::string& name);
// "clean" | "hard" | "wild".
[[nodiscard]] eyetrack::EyeSimPreset eyeSimPreset(const std::string& name);
// "starburst" | "blob".
[[nodiscard]] eyetrack::PupilDetectorKind pupilDetectorKind(const std::string& name);

// eyetrack::makeGazeMapper(), with the missing 3D model reported as what to run.
[[nodiscard]] std::unique_ptr<eyetrack::GazeMapper>
gazeMapper(const eyetrack::EyeCalibration& eye, eyetrack::GazeModel model,
           const std::optional<eyetrack::CameraIntrinsics>& intrinsics);

} // namespace gt::app
