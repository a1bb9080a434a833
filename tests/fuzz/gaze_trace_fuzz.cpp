// Fuzz target: the gaze-trace parser (gaze_trace.hpp). Contract: a malformed file throws
// gt::LoadError naming the file; a trace that loads gives a finite gaze at every time, for
// every eye, inside its units' range.
#include <cmath>
#include <string>

#include "fuzz_input.hpp"

#include "core/error.hpp"
#include "foveation/gaze_trace.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using gt::foveation::GazeEye;
    using gt::fuzz::finding;
    const auto file = gt::fuzz::InputFile::write({data, size}, "gaze.csv");
    try {
        const auto trace = gt::foveation::GazeTrace::load(file);
        if (trace.samples().empty()) finding("a trace without samples loaded");
        if (!(trace.startMs() <= trace.endMs())) finding("a trace that ends before it starts");
        const double mid = trace.startMs() / 2 + trace.endMs() / 2;
        for (const double t :
             {trace.startMs() - 1.0, trace.startMs(), mid, trace.endMs(), trace.endMs() + 1.0}) {
            for (const GazeEye eye : {GazeEye::Both, GazeEye::Left, GazeEye::Right}) {
                const glm::vec2 g = trace.at(t, eye);
                if (!std::isfinite(g.x) || !std::isfinite(g.y))
                    finding("a gaze that is not finite");
            }
        }
    } catch (const gt::LoadError& e) {
        if (std::string(e.what()).find(file.string()) == std::string::npos) {
            finding(std::string("error does not name the file: ") + e.what());
        }
    } catch (const std::exception& e) {
        finding(std::string("not a LoadError: ") + e.what());
    }
    return 0;
}
