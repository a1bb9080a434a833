#pragma once
// The renderer's configuration as typed values. Every choice a front end offers reaches the
// renderer as one of these enums, numbers or structs; front ends (apps/) turn their own strings
// into them, so nothing below apps/ parses an option. The choices the engine and the passes
// define are named here too, so a front end needs this header only.
#include <filesystem>
#include <variant>

#include "display/hmd_profile.hpp"
#include "eccentricity_layers.hpp"
#include "foveation/contrast_sensitivity.hpp"
#include "foveation/eccentricity_layers.hpp"
#include "foveation/interpolation.hpp"
#include "foveation/point_set.hpp"
#include "full_resolution.hpp"
#include "point_set_method.hpp"
#include "trace/integrator.hpp"
#include "view.hpp"
#include "vk/swapchain.hpp"

namespace gt::render {

// The thesis's reconstruction (4.3): nearest neighbour, Modified Shepard, RBF, and the debug
// views of the point set (its points, its cells, its spacing by eccentricity).
using Interpolation = foveation::Interpolation;
using RbfKernel = foveation::RbfKernel;       // multiquadric (thesis eq. 10), Gaussian (eq. 9)
using KnnIndex = foveation::KnnIndex;         // the neighbour lists or the per-pixel table
using PresentMode = vk::PresentMode;          // FIFO, mailbox, immediate
using HmdModel = display::HmdModel;           // the headsets of the HMD path
using DisplayModel = foveation::DisplayModel; // the displays point sets are built for

// What a traced ray computes (PointSetSettings::integrator, ReferenceSettings::integrator):
// the direct integrator or the path tracer, its scattering vertices per path and firefly clamp.
using Integrator = trace::Integrator;
using IntegratorSettings = trace::IntegratorSettings;

// gazetrace: display-referred, guided interpolation, rays rotated every frame, adaptive TAA;
// thesis: the thesis's reconstruction as published (useThesisReconstruction).
enum class Reconstruction { Gazetrace, Thesis };

// The MAR slope m of Guenter et al. 2012's eq. (1) is a number: foveation::kSlopeA, kSlopeB
// (their quality levels) or any positive value (EccentricityLayerSettings::slope).

// Every pixel traced with N jittered rays.
struct FullResolutionConfig {
    passes::ReferenceSettings settings;
};

// The thesis's method: the point set for `params` (loaded from or cached in `cacheDir`) and how
// it is traced and interpolated.
struct PointSetConfig {
    foveation::PointSetParams params;
    std::filesystem::path cacheDir;
    PointSetSettings settings;
};

// Guenter et al. 2012's nested eccentricity layers.
struct LayersConfig {
    EccentricityLayerSettings settings;
};

// A foveation method's own settings.
using MethodConfig = std::variant<FullResolutionConfig, PointSetConfig, LayersConfig>;

// A view's rendering: its method, the reconstruction the point set and TAA follow, and the post
// chain (TAA, the lens; tone mapping at the view's exposure).
struct RenderSettings {
    MethodConfig method;
    Reconstruction reconstruction = Reconstruction::Gazetrace;
    PostSettings post;
};

} // namespace gt::render
