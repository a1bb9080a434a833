#pragma once
// The eye tracker's errors. eyetrack/ stands alone (no engine, no Vulkan), so it has its own
// small hierarchy; the app boundary catches std::exception and prints the one-line message.
#include <stdexcept>
#include <string>

namespace gt::eyetrack {

class EyetrackError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A frame source could not be opened or failed mid-stream; the message names the source.
class CaptureError : public EyetrackError {
public:
    using EyetrackError::EyetrackError;
};

// A file (calibration JSON, truth or target CSV) is malformed; the message names file and reason.
class FormatError : public EyetrackError {
public:
    using EyetrackError::EyetrackError;
};

// Calibration could not be fitted (too few targets, degenerate pupil positions...).
class CalibrationError : public EyetrackError {
public:
    using EyetrackError::EyetrackError;
};

} // namespace gt::eyetrack
