#pragma once
// Options more than one subcommand registers the same way.
#include <cstdint>
#include <string>

namespace CLI {
class App;
}

namespace gt::app {

// --width and --height, each checked to lie in [min, 16384] pixels.
void addSizeOptions(CLI::App* cmd, uint32_t& width, uint32_t& height, uint32_t min,
                    const std::string& what);

// The method settings of the real-time front ends (demo, xr).
void addLiveMethodOptions(CLI::App* cmd, std::string& method, std::string& interp, uint32_t& k,
                          double& scale, uint32_t& raysPerPoint, uint32_t& spp, std::string& taa,
                          std::string& slope, uint32_t& layers);

// Every numeric option of `app` and its subcommands, once all are registered: a FLOAT must be
// a finite number and an unsigned integer must not be negative (CLI11 would wrap it), each
// refused with one line naming the option. Ranges stay with each option.
void addNumberChecks(CLI::App& app);

// --reconstruction gazetrace | thesis, as render and xr take it.
void addReconstructionOption(CLI::App* cmd, std::string& reconstruction);

} // namespace gt::app
