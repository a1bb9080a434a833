#pragma once
// `gazetrace eval`: picture quality measured in the product. A foveated frame (or sequence)
// against a many-ray reference of the same view and gaze — LDR-FLIP, PSNR and SSIM per
// eccentricity band from the display profile's geometry, FLIP also at the resolution the eye
// has in each band (flip_ecc) — beside the uniform baseline that spends the same rays, the
// temporal stability of still, moving-camera and smooth-pursuit sequences, a JSON summary and
// PNGs (error maps, per-band bars, quality against rays).
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "integrator_args.hpp"

namespace gt::app {

struct EvalOptions {
    std::string scene = "builtin:market";
    std::string animation = "all";  // an animated glTF's animation: NAME, INDEX, all or none
    double time = 0.0;              // scene time of every still frame, seconds
    std::string camera;             // --camera X,Y,Z,TX,TY,TZ[,FOV]
    std::string profile = "fove";   // display geometry: size, pixels per degree
    uint32_t width = 0, height = 0; // 0: the profile's; else a window on its screen
    // A headset's left eye instead of --profile: its eye image, off-axis frustum and point-set
    // geometry (a name or custom:WxH@HFOVxVFOV[,HZ]); empty: --profile.
    std::string hmd;
    std::string gaze; // X,Y pixels; empty: the centre (--hmd: the eye's optical axis)
    // The foveated frame.
    std::string method = "points"; // points (the thesis's point set) | layers (Guenter et al.)
    std::string interp = "msm";
    uint32_t k = 10;
    double scale = 1.0;
    uint32_t raysPerPoint = 4;
    // The light transport of every traced frame: the reference, the foveated frame (points)
    // and the uniform baselines and candidates, so that they differ only in where rays go.
    IntegratorArgs integrator;
    bool taa = true;
    double stillClipGamma = 4.0;   // TAA's clipping box with the camera still, the gaze moving
    double eccentricRadius = 0.05; // TAA's eccentric falloff radius, share of the width (0: off)
    // gazetrace (the defaults below) | thesis (render::useThesisReconstruction, which
    // overrides them).
    std::string reconstruction = "gazetrace";
    std::string blend = "display"; // display | linear (the thesis)
    double edgeTolerance = 0.1;    // geometry-aware weights; 0: off
    // Colour-guided weights (0: off) and q: unset, 0.1 and 2 (Renka's), or with the path
    // integrator 0 and 1 (render::useNoisySampleWeights).
    std::optional<double> rangeSigma;
    std::optional<double> shepardPower;
    bool jitter = true;  // per-frame ray rotation inside each disc
    uint32_t frames = 8; // frames rendered before the measured one (TAA settles)
    uint32_t referenceSpp = 64;
    std::string reference; // a reference PNG rendered earlier for the same view (skips it)
    std::string baseline = "uniform"; // uniform | none
    bool temporal = false;            // still-view frame-to-frame change
    std::string cameraPath;           // moving camera: change after reprojection
    std::string pursuit;              // gaze trace CSV over a still scene
    uint32_t sequenceFrames = 12;     // frames of each temporal sequence
    bool sweep = false;               // quality against rays: scales 1, 1.5, 2, 3
    // The speed-up at equal picture quality: the cheapest uniform render whose flip_ecc is no
    // higher than the foveated frame's in every band. "" (off) | uniform (the lowest resolution
    // at the same rays per pixel, upscaled) | full (the fewest rays per pixel at full size).
    std::string match;
    // uniform: how many times the search may double the uniform render's rays per pixel where
    // even full size does not match (unset: kMatchDoublings, up to 8x the rays per point).
    std::optional<uint32_t> matchDoublings;
    std::string out = "out/eval"; // folder for eval.json and the PNGs
    std::string cacheDir;
    bool lod = true;
    bool validate = false; // Khronos validation layer
};

[[nodiscard]] nlohmann::json runEval(const EvalOptions& options);
// The per-band table of a runEval summary, for the terminal.
[[nodiscard]] std::string evalText(const nlohmann::json& summary);

} // namespace gt::app
