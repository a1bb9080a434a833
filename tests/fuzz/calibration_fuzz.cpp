// Fuzz target: the calibration reader (calibration.hpp). Contract: a malformed file throws
// FormatError naming the file; a calibration that loads maps every pupil position a camera can
// report to a finite gaze, so the renderer is never handed NaN.
#include <cmath>
#include <string>

#include "fuzz_input.hpp"

#include "error.hpp"
#include "gaze/calibration.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using gt::fuzz::finding;
    const auto file = gt::fuzz::InputFile::write({data, size}, "calibration.json");
    try {
        const auto c = gt::eyetrack::Calibration::load(file);
        for (const cv::Point2d pupil :
             {cv::Point2d{0, 0}, cv::Point2d{320, 240}, cv::Point2d{1920, 1080}}) {
            const cv::Point2d px = c.map(pupil);
            const cv::Point2d deg = c.mapToAnglesDeg(pupil);
            if (!std::isfinite(px.x) || !std::isfinite(px.y) || !std::isfinite(deg.x) ||
                !std::isfinite(deg.y)) {
                finding("a loaded calibration maps a pupil to a gaze that is not finite");
            }
        }
    } catch (const gt::eyetrack::FormatError& e) {
        if (std::string(e.what()).find(file.string()) == std::string::npos) {
            finding(std::string("error does not name the file: ") + e.what());
        }
    } catch (const std::exception& e) {
        finding(std::string("not a FormatError: ") + e.what());
    }
    return 0;
}
