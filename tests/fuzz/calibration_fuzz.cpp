// Fuzz target: the calibration reader (gaze/calibration_set.hpp: version 3 with per-eye entries
// and the 3D model, and version 2). Contract: a malformed file throws FormatError naming the
// file; a calibration that loads maps every pupil a camera can report — through the polynomial,
// and through the 3D eye model where the file has one — to a finite gaze or to none, so the
// renderer is never handed NaN.
#include <cmath>
#include <string>

#include "fuzz_input.hpp"

#include "error.hpp"
#include "gaze/calibration.hpp"
#include "gaze/calibration_set.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using gt::fuzz::finding;
    const auto file = gt::fuzz::InputFile::write({data, size}, "calibration.json");
    try {
        const auto set = gt::eyetrack::CalibrationSet::load(file);
        for (const auto& eye : set.eyes) {
            const auto& c = eye.poly;
            for (const cv::Point2d pupil :
                 {cv::Point2d{0, 0}, cv::Point2d{320, 240}, cv::Point2d{1920, 1080}}) {
                const cv::Point2d px = c.map(pupil);
                const cv::Point2d deg = c.mapToAnglesDeg(pupil);
                if (!std::isfinite(px.x) || !std::isfinite(px.y) || !std::isfinite(deg.x) ||
                    !std::isfinite(deg.y)) {
                    finding("a loaded calibration maps a pupil to a gaze that is not finite");
                }
            }
            if (!eye.model3d) {
                continue;
            }
            const auto mapper = gt::eyetrack::makeGazeMapper(eye, gt::eyetrack::GazeModel::ThreeD);
            for (const cv::RotatedRect e :
                 {cv::RotatedRect({160, 120}, {40, 30}, 20), cv::RotatedRect({5, 5}, {3, 2}, 0),
                  cv::RotatedRect({300, 230}, {90, 12}, 80)}) {
                gt::eyetrack::PupilResult p;
                p.found = true;
                p.confidence = 1.0;
                p.ellipse = e;
                if (const auto g = mapper->map(p, 0.0);
                    g && (!std::isfinite(g->x) || !std::isfinite(g->y))) {
                    finding("the 3D model maps a pupil to a gaze that is not finite");
                }
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
