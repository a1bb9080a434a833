#pragma once
// The command line's option values as the renderer's typed settings (renderer/settings.hpp):
// every string an option takes becomes an enum or a number here, and only here. A bad value
// throws ArgumentError naming the option and the values it takes.
#include <string>
#include <vector>

#include "settings.hpp"

namespace gt::app {

[[nodiscard]] render::Interpolation parseInterpolation(const std::string& name); // nn | msm | rbf
[[nodiscard]] render::RbfKernel parseKernel(const std::string& name);   // multiquadric | gaussian
[[nodiscard]] render::KnnIndex parseKnnIndex(const std::string& name);  // lists | table
[[nodiscard]] render::Interpolation parseView(const std::string& name); // points|cells|eccentricity
[[nodiscard]] render::Reconstruction
parseReconstruction(const std::string& name); // gazetrace|thesis
// --slope: "A", "B" (Guenter et al. 2012's quality levels) or a positive MAR slope.
[[nodiscard]] double parseSlope(const std::string& text);
[[nodiscard]] render::PresentMode
parsePresentMode(const std::string& name); // fifo|mailbox|immediate

// --hmd: fove | vive | rift-cv1.
[[nodiscard]] render::HmdModel parseHmd(const std::string& name);
[[nodiscard]] display::HmdProfile hmdProfile(const std::string& name);
[[nodiscard]] std::vector<std::string> hmdProfileNames();
// --profile: fove | vive | desktop.
[[nodiscard]] render::DisplayModel parseDisplay(const std::string& name);
[[nodiscard]] foveation::DisplayProfile displayProfile(const std::string& name);
[[nodiscard]] std::vector<std::string> displayProfileNames();

} // namespace gt::app
