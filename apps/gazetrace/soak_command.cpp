// `gazetrace soak` (soak_command.hpp). The frame loop a long demo session runs, compressed:
//  - the gaze pursues a Lissajous path and jumps (a saccade, reported as such) every 40 frames;
//  - the camera turns slowly back and forth, so TAA reprojects;
//  - every 15 frames the settings change, through eight phases: nearest neighbour at one ray
//    and at two with TAA off, Modified Shepard through the per-pixel k-NN table and through the
//    neighbour lists, the full-resolution reference, a phase read back to host memory, an
//    animated scene (--animated-scene: a second scene on the same renderer, its two-level
//    structure refitted and uploaded every frame, its samples carrying motion into TAA), and
//    the path integrator at two bounces.
// The eight phases make a 120-frame cycle. What a phase builds lives while it runs (the k-NN
// table of the MSM phase takes ~380 MB at 1920 x 1080 and is released when the settings
// change), so resident memory is compared between frames at the same point of the cycle once
// every phase has run: frame 120 and the last of 240, 360, ..., 960. Growth between them is
// what the loop itself keeps. RBF is left out: its per-pixel weights at 1920 x 1080 take minutes to
// build on the CPU driver and add nothing the MSM variants do not exercise.
#include "soak_command.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <unistd.h>

#include <glm/gtc/matrix_transform.hpp>

#include "bench_command.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "foveation/contrast_sensitivity.hpp"
#include "frame_loop.hpp"
#include "full_resolution.hpp"
#include "method_choice.hpp"
#include "method_factory.hpp"
#include "option_parsing.hpp"
#include "output_target.hpp"
#include "point_set_method.hpp"
#include "renderer.hpp"
#include "vk/context.hpp"

namespace gt::app {

namespace {

// Resident set size from /proc/self/statm (pages), in MiB.
double residentMiB() {
    std::ifstream statm("/proc/self/statm");
    unsigned long long size = 0, resident = 0;
    if (!(statm >> size >> resident)) throw Error("soak: cannot read /proc/self/statm");
    return static_cast<double>(resident) * static_cast<double>(::sysconf(_SC_PAGESIZE)) /
           (1024.0 * 1024.0);
}

struct Phase {
    const char* name;
    bool reference = false; // the full-resolution method instead of the point set
    passes::Interpolation interpolation = passes::Interpolation::Nearest;
    passes::KnnIndex knn = passes::KnnIndex::PixelTable;
    uint32_t k = 10;
    uint32_t raysPerPoint = 1;
    bool taa = true;
    bool readback = false;
    bool animated = false; // the animated scene instead of --scene
    bool path = false;     // the path integrator (2 bounces) instead of the direct one
};

constexpr uint32_t kPhaseFrames = 15;
constexpr uint32_t kSaccadeEvery = 40;

const Phase kPhases[] = {
    {"nn/1 ray/taa"},
    {"msm/table k10/2 rays/taa", false, passes::Interpolation::Shepard,
     passes::KnnIndex::PixelTable, 10, 2},
    {"nn/2 rays/no taa", false, passes::Interpolation::Nearest, passes::KnnIndex::PixelTable, 10, 2,
     false},
    {"msm/lists k6/1 ray/taa", false, passes::Interpolation::Shepard,
     passes::KnnIndex::NeighbourLists, 6},
    {"reference/1 ray/no taa", true, passes::Interpolation::Nearest, passes::KnnIndex::PixelTable,
     10, 1, false},
    {"nn/1 ray/taa/readback", false, passes::Interpolation::Nearest, passes::KnnIndex::PixelTable,
     10, 1, true, true},
    {"animated/nn/1 ray/taa", false, passes::Interpolation::Nearest, passes::KnnIndex::PixelTable,
     10, 1, true, false, true},
    {"nn/path 2 bounces/1 ray/taa", false, passes::Interpolation::Nearest,
     passes::KnnIndex::PixelTable, 10, 1, true, false, false, true},
};
constexpr uint32_t kCycleFrames = std::size(kPhases) * kPhaseFrames; // 120
// The growth is measured from here: every phase has run once, its pipelines and tables built.
constexpr uint32_t kReferenceFrame = kCycleFrames;

// The gaze of a soak frame: a Lissajous pursuit around a centre that jumps (a saccade) every
// kSaccadeEvery frames.
struct SoakGaze {
    glm::vec2 pixel{};
    bool saccade = false;
};

class SoakGazeSource {
public:
    SoakGazeSource(uint32_t width, uint32_t height)
        : mW(static_cast<float>(width)), mH(static_cast<float>(height)),
          mCentre(0.5f * mW, 0.5f * mH) {}
    SoakGaze at(uint32_t i) {
        const bool saccade = i > 0 && i % kSaccadeEvery == 0;
        if (saccade) {
            mCentre = {mW * (0.5f + mJump(mRng)), mH * (0.5f + mJump(mRng))};
            ++mSaccades;
        }
        const float t = static_cast<float>(i) / 60.0f; // as if at 60 Hz
        const float tau = 2.0f * std::numbers::pi_v<float>;
        return {glm::clamp(mCentre + glm::vec2(0.15f * mW * std::sin(tau * 0.23f * t),
                                               0.12f * mH * std::sin(tau * 0.31f * t)),
                           glm::vec2(0.0f), glm::vec2(mW - 1.0f, mH - 1.0f)),
                saccade};
    }
    [[nodiscard]] uint64_t saccades() const noexcept { return mSaccades; }

private:
    float mW, mH;
    glm::vec2 mCentre;
    std::mt19937 mRng{20};
    std::uniform_real_distribution<float> mJump{-0.3f, 0.3f};
    uint64_t mSaccades = 0;
};

// Resident memory at the frames that are compared (the same point of the phase cycle) and at
// every hundredth, with the validation errors so far.
struct MemoryTrace {
    nlohmann::json samples = nlohmann::json::array();
    double referenceMiB = 0.0, comparedMiB = 0.0;
    uint32_t comparedFrame = 0;

    void frameDone(uint32_t frame, uint32_t frames, const vk::Context& ctx, double seconds,
                   bool quiet) {
        const bool comparable =
            frame >= kReferenceFrame && (frame - kReferenceFrame) % kCycleFrames == 0;
        if (!comparable && frame % 100 != 0 && frame != frames) return;
        const double mib = residentMiB();
        if (frame == kReferenceFrame) referenceMiB = mib;
        if (comparable) {
            comparedMiB = mib;
            comparedFrame = frame;
        }
        samples.push_back({{"frame", frame},
                           {"resident_mib", mib},
                           {"same_point_of_cycle", comparable},
                           {"seconds", seconds},
                           {"validation_errors", ctx.validationErrors()}});
        if (!quiet) {
            std::fprintf(stderr,
                         "soak: frame %u, %.1f MiB resident, %.1f s, %u validation "
                         "errors\n",
                         frame, mib, seconds, ctx.validationErrors());
        }
    }
};

// The summary, and the failures it shows: validation errors, or memory growth above the limit.
nlohmann::json soakSummary(const SoakOptions& o, render::Renderer& r, const MemoryTrace& memory,
                           double seconds, uint64_t rays, uint64_t saccades,
                           uint64_t readbackBytes) {
    const uint32_t errors = r.context().validationErrors();
    const bool measured = memory.comparedFrame > kReferenceFrame;
    const double growth =
        measured ? 100.0 * (memory.comparedMiB - memory.referenceMiB) / memory.referenceMiB : 0.0;
    nlohmann::json phases = nlohmann::json::array();
    for (const Phase& p : kPhases)
        phases.push_back(p.name);
    nlohmann::json result = {
        {"device", r.context().deviceName()},
        {"scene", o.scene},
        {"width", o.width},
        {"height", o.height},
        {"frames", o.frames},
        {"seconds", seconds},
        {"ms_per_frame", 1000.0 * seconds / o.frames},
        // Per frame (the mean over the run's phases), as every command reports rays.
        {"rays", o.frames ? (rays + o.frames / 2) / o.frames : 0},
        {"rays_total", rays},
        {"saccades", saccades},
        {"readback_bytes", readbackBytes},
        {"phases", phases},
        {"frames_per_phase", kPhaseFrames},
        {"validation", "khronos + synchronization"},
        {"validation_errors", errors},
        {"validation_warnings", r.context().validationWarnings()},
        {"resident_mib", memory.samples},
        {"growth_from_frame", kReferenceFrame},
        {"growth_to_frame",
         measured ? nlohmann::json(memory.comparedFrame) : nlohmann::json(nullptr)},
        {"growth_percent", measured ? nlohmann::json(growth) : nlohmann::json(nullptr)},
        {"max_growth_percent", o.maxGrowthPercent}};
    if (!o.json.empty()) writeJsonFile(o.json, result);
    if (errors > 0) {
        const std::vector<std::string> messages = r.context().validationMessages();
        throw Error("soak: " + std::to_string(errors) + " validation error(s) in " +
                    std::to_string(o.frames) + " frames" +
                    (messages.empty() ? std::string() : " (the first: " + messages.front() + ")"));
    }
    if (measured && growth > o.maxGrowthPercent) {
        char what[200];
        std::snprintf(what, sizeof(what),
                      "soak: resident memory grew %.1f%% from frame %u to frame %u (%.1f -> %.1f "
                      "MiB), more than %.1f%%",
                      growth, kReferenceFrame, memory.comparedFrame, memory.referenceMiB,
                      memory.comparedMiB, o.maxGrowthPercent);
        throw Error(what);
    }
    return result;
}

} // namespace

// The animated phase's scene: --animated-scene on the renderer beside --scene. When the shipped
// sample is not found from here (the default path is relative), the phase shows --scene.
struct AnimatedPhase {
    std::unique_ptr<render::PointSetMethod> method;
    scene::Camera camera;
    float exposure = 1.0f;
};

AnimatedPhase animatedPhase(render::Renderer& r, const SoakOptions& o,
                            const foveation::PointSetParams& params) {
    render::Renderer::SceneId id = 0;
    if (o.animatedSceneGiven || std::filesystem::exists(o.animatedScene)) {
        id = r.addScene(o.animatedScene, gltfLoadOptions());
    } else {
        log::info("soak: " + o.animatedScene +
                  " not found from here: the animated phase shows --scene");
    }
    AnimatedPhase a;
    a.method = render::makeMethod(render::PointSetConfig{params, cacheFolder(o.cacheDir), {}},
                                  r.methodContext(id));
    a.camera = r.scene(id).camera;
    a.exposure = r.scene(id).exposure;
    return a;
}

nlohmann::json runSoak(const SoakOptions& o) {
    if (o.frames < 1) throw ArgumentError("soak: --frames must be at least 1");
    render::Renderer r({.scene = o.scene,
                        .validate = true, // Khronos validation and synchronisation validation
                        .framesInFlight = 0,
                        .deviceOverride = deviceRequest(),
                        .sceneLoad = gltfLoadOptions()});
    foveation::PointSetParams params;
    params.display = foveation::windowProfile(
        foveation::displayProfile(foveation::DisplayModel::Desktop), o.width, o.height);
    const std::unique_ptr<render::PointSetMethod> foveated =
        makePointSetMethod(r, params, o.cacheDir);
    const AnimatedPhase animated = animatedPhase(r, o, params);
    render::FullResolution reference(r.methodContext(), {1, 0});
    render::DiscardTarget discard;
    render::ReadbackTarget readback(r.context());

    const scene::Camera home = r.scene().camera;
    SoakGazeSource gaze(o.width, o.height);
    MemoryTrace memory;
    uint64_t rays = 0, readbackBytes = 0;
    const auto phaseOf = [](uint32_t i) -> const Phase& {
        return kPhases[(i / kPhaseFrames) % std::size(kPhases)];
    };
    FrameStages<SoakGaze> stages;
    stages.gaze = [&](const FrameTick& t) { return gaze.at(t.index); };
    stages.views = [&](const FrameTick& tick, const SoakGaze& g) {
        const Phase& phase = phaseOf(tick.index);
        const float t = static_cast<float>(tick.index) / 60.0f; // as if at 60 Hz
        const float tau = 2.0f * std::numbers::pi_v<float>;
        render::View v;
        v.width = o.width;
        v.height = o.height;
        v.gaze = g.pixel;
        v.saccade = g.saccade;
        v.camera = home;
        const glm::mat4 turn =
            glm::rotate(glm::mat4(1.0f), 0.15f * std::sin(tau * 0.05f * t), home.up);
        v.camera.forward = glm::vec3(turn * glm::vec4(home.forward, 0.0f));
        v.exposure = r.scene().exposure;
        v.post.taa = phase.taa;
        foveated->settings.raysPerPoint = phase.raysPerPoint;
        foveated->settings.interpolation.method = phase.interpolation;
        foveated->settings.interpolation.knn = phase.knn;
        foveated->settings.interpolation.k = phase.k;
        foveated->settings.integrator = {};
        if (phase.path) {
            foveated->settings.integrator.integrator = render::Integrator::Path;
            foveated->settings.integrator.bounces = 2;
        }
        v.method = phase.reference ? static_cast<render::FoveationMethod*>(&reference)
                                   : static_cast<render::FoveationMethod*>(foveated.get());
        if (phase.animated) {
            animated.method->settings = foveated->settings;
            v.method = animated.method.get();
            v.camera = animated.camera;
            v.exposure = animated.exposure;
            v.name = "animated";
        }
        return std::vector<render::View>{v};
    };
    stages.targets = [&](const FrameTick& t, std::span<const render::View>) {
        return std::vector<render::OutputTarget*>{
            phaseOf(t.index).readback ? static_cast<render::OutputTarget*>(&readback)
                                      : static_cast<render::OutputTarget*>(&discard)};
    };
    const auto start = std::chrono::steady_clock::now();
    const auto secondsSince = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    stages.done = [&](const FrameTick& t, const SoakGaze&, std::span<const render::View>,
                      const render::FrameResult& f) {
        for (const auto& view : f.views)
            rays += view.rays;
        if (phaseOf(t.index).readback) readbackBytes += readback.takePixels().size();
        (void)r.takeCompleted();
        memory.frameDone(t.index + 1, o.frames, r.context(), secondsSince(), o.quiet);
        return true;
    };
    (void)runFrameLoop(r, FrameClock(), o.frames, stages);
    r.waitIdle();
    return soakSummary(o, r, memory, secondsSince(), rays, gaze.saccades(), readbackBytes);
}

} // namespace gt::app
