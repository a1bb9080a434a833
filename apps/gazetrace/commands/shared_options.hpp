#pragma once
// Options more than one subcommand registers the same way.
#include <cstdint>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "atomic_write.hpp"
#include "integrator_args.hpp"

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

// --animation NAME|INDEX|all|none and --time T0: which of an animated scene's animations play,
// and the scene time of the first frame in seconds (not negative).
void addAnimationOptions(CLI::App* cmd, std::string& animation, double& startSeconds);

// --integrator direct | path, --bounces N and --sequence sobol | independent (option_parsing's
// IntegratorArgs); `who` says which of the command's methods trace with it.
void addIntegratorOptions(CLI::App* cmd, IntegratorArgs& args, const std::string& who);

// --reconstruction gazetrace | thesis, as render and xr take it.
void addReconstructionOption(CLI::App* cmd, std::string& reconstruction);

// The file a value reads, for io::refuseOutputThatIsInput: a path, or the FILE of video:FILE,
// images:DIR, trace:FILE and track:SOURCE; none (an empty path) for builtin: scenes, synthetic:
// and v4l2: sources and the gaze inputs that read no file.
[[nodiscard]] io::RunFile inputFile(const std::string& option, const std::string& value);

// Before any work: every output file passes io::checkOutputFile (a long run does not find out
// at its end that it cannot write), and io::refuseOutputThatIsInput holds over the outputs and
// the inputs ({option, value} pairs, read as inputFile() reads them). Throws io::WriteError.
void checkRunFiles(const std::vector<io::RunFile>& outputs,
                   std::initializer_list<std::pair<const char*, std::string>> inputs);

} // namespace gt::app
