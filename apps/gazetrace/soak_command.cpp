// `gazetrace soak` (soak_command.hpp). The frame loop a long demo session runs, compressed:
//  - the gaze pursues a Lissajous path and jumps (a saccade, reported as such) every 40 frames;
//  - the camera turns slowly back and forth, so TAA reprojects;
//  - every 15 frames the settings change, through six phases: nearest neighbour at one ray and
//    at two with TAA off, Modified Shepard through the per-pixel k-NN table and through the
//    neighbour lists, the full-resolution reference, and a phase read back to host memory.
// The six phases make a 90-frame cycle. What a phase builds lives while it runs (the k-NN
// table of the MSM phase takes ~380 MB at 1920 x 1080 and is released when the settings
// change), so resident memory is compared between frames at the same point of the cycle:
// frame 100 and the last of 190, 280, ..., 1000. Growth between them is what the loop itself
// keeps. RBF is left out: its per-pixel weights at 1920 x 1080 take minutes to build on the
// CPU driver and add nothing the MSM variants do not exercise.
#include "soak_command.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <unistd.h>

#include <glm/gtc/matrix_transform.hpp>

#include "bench_command.hpp"
#include "core/error.hpp"
#include "foveation/contrast_sensitivity.hpp"
#include "foveation/point_set_cache.hpp"
#include "full_resolution.hpp"
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
};

constexpr uint32_t kPhaseFrames = 15;
constexpr uint32_t kSaccadeEvery = 40;
constexpr uint32_t kReferenceFrame = 100; // the growth is measured from here

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
};
constexpr uint32_t kCycleFrames = std::size(kPhases) * kPhaseFrames; // 90

} // namespace

nlohmann::json runSoak(const SoakOptions& o) {
    if (o.frames < 1) throw ArgumentError("soak: --frames must be at least 1");
    const std::filesystem::path cache =
        o.cacheDir.empty() ? defaultCacheDir() : std::filesystem::path(o.cacheDir);
    render::Renderer r({.scene = o.scene,
                        .validate = true, // Khronos validation and synchronisation validation
                        .framesInFlight = 0,
                        .deviceOverride = deviceRequest(),
                        .sceneLoad = gltfLoadOptions()});
    foveation::PointSetParams params;
    params.display = foveation::windowProfile(
        foveation::displayProfile(foveation::DisplayModel::Desktop), o.width, o.height);
    render::PointSetMethod foveated(r.methodContext(), params, cache);
    render::FullResolution reference(r.methodContext(), {1, 0});
    render::DiscardTarget discard;
    render::ReadbackTarget readback(r.context());

    const scene::Camera home = r.scene().camera;
    const auto w = static_cast<float>(o.width), h = static_cast<float>(o.height);
    std::mt19937 rng(20);
    std::uniform_real_distribution<float> jump(-0.3f, 0.3f);
    glm::vec2 centre{0.5f * w, 0.5f * h};

    nlohmann::json samples = nlohmann::json::array();
    double referenceMiB = 0.0, comparedMiB = 0.0;
    uint32_t comparedFrame = 0;
    uint64_t rays = 0, saccades = 0, readbackBytes = 0;
    const auto start = std::chrono::steady_clock::now();
    for (uint32_t i = 0; i < o.frames; ++i) {
        const Phase& phase = kPhases[(i / kPhaseFrames) % std::size(kPhases)];
        const bool saccade = i > 0 && i % kSaccadeEvery == 0;
        if (saccade) {
            centre = {w * (0.5f + jump(rng)), h * (0.5f + jump(rng))};
            ++saccades;
        }
        const float t = static_cast<float>(i) / 60.0f; // as if at 60 Hz
        const float tau = 2.0f * std::numbers::pi_v<float>;
        render::View v;
        v.width = o.width;
        v.height = o.height;
        v.gaze = glm::clamp(centre + glm::vec2(0.15f * w * std::sin(tau * 0.23f * t),
                                               0.12f * h * std::sin(tau * 0.31f * t)),
                            glm::vec2(0.0f), glm::vec2(w - 1.0f, h - 1.0f));
        v.saccade = saccade;
        v.camera = home;
        const glm::mat4 turn =
            glm::rotate(glm::mat4(1.0f), 0.15f * std::sin(tau * 0.05f * t), home.up);
        v.camera.forward = glm::vec3(turn * glm::vec4(home.forward, 0.0f));
        v.exposure = r.scene().exposure;
        v.post.taa = phase.taa;
        foveated.settings.raysPerPoint = phase.raysPerPoint;
        foveated.settings.interpolation.method = phase.interpolation;
        foveated.settings.interpolation.knn = phase.knn;
        foveated.settings.interpolation.k = phase.k;
        v.method = phase.reference ? static_cast<render::FoveationMethod*>(&reference)
                                   : static_cast<render::FoveationMethod*>(&foveated);
        render::OutputTarget* target = phase.readback
                                           ? static_cast<render::OutputTarget*>(&readback)
                                           : static_cast<render::OutputTarget*>(&discard);
        const render::FrameResult f = r.renderFrame({&v, 1}, {&target, 1});
        for (const auto& view : f.views)
            rays += view.rays;
        if (phase.readback) readbackBytes += readback.takePixels().size();
        (void)r.takeCompleted();
        const uint32_t frame = i + 1;
        const bool comparable =
            frame >= kReferenceFrame && (frame - kReferenceFrame) % kCycleFrames == 0;
        if (comparable || frame % 100 == 0 || frame == o.frames) {
            const double mib = residentMiB();
            if (frame == kReferenceFrame) referenceMiB = mib;
            if (comparable) {
                comparedMiB = mib;
                comparedFrame = frame;
            }
            const double s =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            samples.push_back({{"frame", frame},
                               {"resident_mib", mib},
                               {"same_point_of_cycle", comparable},
                               {"seconds", s},
                               {"validation_errors", r.context().validationErrors()}});
            if (!o.quiet) {
                std::fprintf(stderr,
                             "soak: frame %u, %.1f MiB resident, %.1f s, %u validation "
                             "errors\n",
                             frame, mib, s, r.context().validationErrors());
            }
        }
    }
    r.waitIdle();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const uint32_t errors = r.context().validationErrors();
    const bool measured = comparedFrame > kReferenceFrame;
    const double growth = measured ? 100.0 * (comparedMiB - referenceMiB) / referenceMiB : 0.0;
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
        {"rays", rays},
        {"saccades", saccades},
        {"readback_bytes", readbackBytes},
        {"phases", phases},
        {"frames_per_phase", kPhaseFrames},
        {"validation", "khronos + synchronization"},
        {"validation_errors", errors},
        {"validation_warnings", r.context().validationWarnings()},
        {"resident_mib", samples},
        {"growth_from_frame", kReferenceFrame},
        {"growth_to_frame", measured ? nlohmann::json(comparedFrame) : nlohmann::json(nullptr)},
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
                      growth, kReferenceFrame, comparedFrame, referenceMiB, comparedMiB,
                      o.maxGrowthPercent);
        throw Error(what);
    }
    return result;
}

} // namespace gt::app
