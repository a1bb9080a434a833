#pragma once
// Which light transport the tracing passes (reference, point_sample) compute per ray: the
// direct integrator of shaders/common/trace.glsl (direct light, hard shadows, one mirror
// bounce, the sky as ambient) or the path tracer of shaders/common/path.glsl. Each choice is a
// pipeline of its own (specialisation constants, trace_shared.h): the direct pipelines are
// built exactly as without this choice.
#include <cstdint>

#include "trace_shared.h"

namespace gt::trace {

enum class Integrator : uint32_t {
    Direct = shaders::trace::kIntegratorDirect,
    Path = shaders::trace::kIntegratorPath,
    // Verification only (tests): the same paths estimated by uniform hemisphere sampling with
    // emission gathered only where a path hits an emitter (no next-event estimation, no MIS).
    // Unbiased for the same integral as Path, and far noisier.
    BruteForce = shaders::trace::kIntegratorBruteForce,
};

inline constexpr uint32_t kMaxBounces = 64;

// What a path's random decisions draw from (shaders/shared/sequence_shared.h).
enum class SampleSequence : uint32_t {
    // Owen-scrambled Sobol' points indexed by frame and ray: the rays and frames a pixel
    // pools are stratified in every decision.
    Sobol = shaders::trace::kSequenceSobol,
    // Independent pseudo-random numbers per (pixel or point, ray, frame).
    Independent = shaders::trace::kSequenceIndependent,
};

struct IntegratorSettings {
    Integrator integrator = Integrator::Direct;
    // Path: scattering vertices per path (1: direct light at the first hit only). 1 to
    // kMaxBounces.
    uint32_t bounces = 4;
    // Path: an indirect contribution (light reaching the eye through two or more scattering
    // vertices) is scaled down to at most this luminance; 0: off (unbiased). Clamping trades a
    // darkening of caustics and glossy interreflections for the fireflies a few paths per
    // pixel would otherwise leave for the denoiser.
    float fireflyClamp = 10.0f;
    SampleSequence sequence = SampleSequence::Sobol;

    friend bool operator==(const IntegratorSettings&, const IntegratorSettings&) = default;
};

} // namespace gt::trace
