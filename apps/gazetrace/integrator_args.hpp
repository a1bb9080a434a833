#pragma once
// The integrator options as the command line gives them (addIntegratorOptions registers them,
// parseIntegrator turns them into trace::IntegratorSettings).
#include <cstdint>
#include <string>

namespace gt::app {

struct IntegratorArgs {
    std::string integrator = "direct"; // direct | path
    uint32_t bounces = 4;              // 1 to trace::kMaxBounces
    std::string sequence = "sobol";    // sobol | independent
    std::string denoise = "off";       // off | on: the post chain's denoiser (pass `denoise`)
    uint32_t foveaRays = 0; // point sets: rays per point within 5 degrees of the gaze (0: same)
};

} // namespace gt::app
