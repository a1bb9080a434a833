#include "study_stimuli.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <utility>
#include <variant>

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/progress.hpp"
#include "method_choice.hpp"
#include "method_factory.hpp"
#include "output_target.hpp"
#include "view_args.hpp"

namespace gt::app {

namespace {

passes::Interpolation interpolationOf(study::Interpolation i) {
    switch (i) {
    case study::Interpolation::ModifiedShepard:
        return passes::Interpolation::Shepard;
    case study::Interpolation::Rbf:
        return passes::Interpolation::Rbf;
    case study::Interpolation::NearestNeighbour:
        break;
    }
    return passes::Interpolation::Nearest;
}

const char* interpolationWord(study::Interpolation i) {
    switch (i) {
    case study::Interpolation::ModifiedShepard:
        return "msm";
    case study::Interpolation::Rbf:
        return "rbf";
    case study::Interpolation::NearestNeighbour:
        break;
    }
    return "nn";
}

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

// The camera of a design's scene entry: its --camera text, checked as render checks it but named
// as the design's.
scene::Camera fixedCamera(const study::SceneChoice& scene, const scene::Camera& own) {
    if (scene.camera.empty()) {
        return own;
    }
    try {
        return parseCamera(scene.camera)->camera(own.yfov);
    } catch (const ArgumentError& e) {
        throw ArgumentError("scene " + scene.scene + ": camera '" + scene.camera +
                            "': " + e.what());
    }
}

} // namespace

StimulusDisplay desktopStimulusDisplay(uint32_t width, uint32_t height) {
    const foveation::DisplayProfile desktop =
        foveation::displayProfile(foveation::DisplayModel::Desktop);
    // Point sets: the window on the desktop screen (demo's forSize); layers: the screen itself,
    // which the method sizes per view.
    return {foveation::windowProfile(desktop, width, height), desktop, false};
}

render::RenderSettings renderSettingsOf(const study::RenderChoice& c,
                                        const StimulusDisplay& display,
                                        const std::filesystem::path& cacheDir) {
    render::RenderSettings s;
    s.post.taa = c.taa;
    switch (c.method) {
    case study::Method::Reference:
        s.method = render::FullResolutionConfig{{c.spp, 0}};
        break;
    case study::Method::Layers: {
        render::EccentricityLayerSettings layers;
        layers.slope = c.slope;
        layers.layers = c.layers;
        layers.raysPerPixel = c.spp;
        layers.temporal = c.taa;
        layers.display = display.layers;
        s.method = render::LayersConfig{layers};
        break;
    }
    case study::Method::Foveated: {
        render::PointSetConfig p;
        p.params.display = display.pointSets;
        p.params.scale = c.scale;
        p.cacheDir = cacheDir;
        p.settings.raysPerPoint = c.raysPerPoint;
        p.settings.interpolation.method = interpolationOf(c.interp);
        p.settings.interpolation.k = c.k;
        p.settings.displaySpace = display.displaySpace;
        s.method = std::move(p);
        break;
    }
    }
    return s;
}

std::string describe(const study::RenderChoice& c) {
    switch (c.method) {
    case study::Method::Reference:
        return "reference spp " + std::to_string(c.spp) + (c.taa ? "" : " no-taa");
    case study::Method::Layers:
        return "layers slope " + number(c.slope) + " layers " + std::to_string(c.layers) + " spp " +
               std::to_string(c.spp) + (c.taa ? "" : " no-taa");
    case study::Method::Foveated:
        break;
    }
    return "foveated scale " + number(c.scale) + " rays-per-point " +
           std::to_string(c.raysPerPoint) + " interp " + interpolationWord(c.interp) + " k " +
           std::to_string(c.k) + (c.taa ? "" : " no-taa");
}

std::vector<std::string> scenesOf(std::span<const study::Stimulus> stimuli) {
    std::vector<std::string> scenes;
    for (const study::Stimulus& s : stimuli) {
        if (std::find(scenes.begin(), scenes.end(), s.scene.scene) == scenes.end()) {
            scenes.push_back(s.scene.scene);
        }
    }
    return scenes;
}

StudyStimuli::StudyStimuli(render::Renderer& renderer, std::vector<std::string> scenes,
                           const std::string& cacheDir)
    : mRenderer(renderer), mScenes(std::move(scenes)), mCacheDir(cacheFolder(cacheDir)) {}

StudyStimuli::~StudyStimuli() = default;

render::Renderer::SceneId StudyStimuli::sceneId(const std::string& spec) const {
    const auto it = std::find(mScenes.begin(), mScenes.end(), spec);
    if (it == mScenes.end()) {
        throw Error("study: the renderer holds no scene " + spec);
    }
    return static_cast<render::Renderer::SceneId>(it - mScenes.begin());
}

float StudyStimuli::exposure(const study::Stimulus& stimulus) const {
    return mRenderer.scene(sceneId(stimulus.scene.scene)).exposure;
}

render::FoveationMethod& StudyStimuli::method(const study::Stimulus& stimulus,
                                              const StimulusDisplay& display, uint32_t width,
                                              uint32_t height) {
    const Key key{stimulus.scene.scene, describe(stimulus.render), width, height};
    auto it = mMethods.find(key);
    if (it == mMethods.end()) {
        // Point sets are built for the view's own size: a window on the display's screen.
        StimulusDisplay sized = display;
        if (sized.pointSets.width != width || sized.pointSets.height != height) {
            sized.pointSets = foveation::windowProfile(display.pointSets, width, height);
        }
        const render::RenderSettings settings = renderSettingsOf(stimulus.render, sized, mCacheDir);
        const render::MethodContext context =
            mRenderer.methodContext(sceneId(stimulus.scene.scene));
        Built b{stimulus.render, render::makeMethod(settings.method, context), 0};
        if (const auto* p = dynamic_cast<const render::PointSetMethod*>(b.method.get())) {
            b.points = p->pointSet().points().size();
            log::info("study: point set for " + describe(stimulus.render) + " at " +
                      std::to_string(width) + "x" + std::to_string(height) + ": " +
                      std::to_string(b.points) + " points");
        }
        it = mMethods.emplace(key, std::move(b)).first;
    }
    return *it->second.method;
}

render::PostSettings StudyStimuli::post(const study::Stimulus& stimulus) {
    render::PostSettings post;
    post.taa = stimulus.render.taa;
    return post;
}

scene::Camera StudyStimuli::camera(const study::SceneChoice& scene, double ms) {
    const scene::Camera own = fixedCamera(scene, mRenderer.scene(sceneId(scene.scene)).camera);
    if (scene.cameraPath.empty()) {
        return own;
    }
    auto it = mPaths.find(scene.cameraPath);
    if (it == mPaths.end()) {
        it = mPaths.emplace(scene.cameraPath, scene::CameraPath::load(scene.cameraPath)).first;
    }
    // Every interval replays the path from its start: both intervals of a trial move alike.
    return it->second.at(it->second.startMs() + ms, own.yfov);
}

render::View StudyStimuli::view(const study::Stimulus& stimulus, const StimulusDisplay& display,
                                uint32_t width, uint32_t height, glm::vec2 gazePx, double ms) {
    render::View v;
    v.camera = camera(stimulus.scene, ms);
    v.width = width;
    v.height = height;
    v.gaze = gazePx;
    v.exposure = exposure(stimulus);
    v.method = &method(stimulus, display, width, height);
    v.post = post(stimulus);
    return v;
}

void StudyStimuli::prepare(std::span<const study::Stimulus> stimuli, const StimulusDisplay& display,
                           uint32_t width, uint32_t height) {
    std::vector<const study::Stimulus*> mine;
    for (const study::Stimulus& s : stimuli) {
        if (std::find(mScenes.begin(), mScenes.end(), s.scene.scene) != mScenes.end()) {
            mine.push_back(&s);
        }
    }
    const auto start = std::chrono::steady_clock::now();
    progress::Step step("study: building the stimuli", mine.size());
    render::DiscardTarget sink;
    render::OutputTarget* const target = &sink;
    const glm::vec2 centre(0.5f * static_cast<float>(width), 0.5f * static_cast<float>(height));
    for (const study::Stimulus* s : mine) {
        // One frame of each: pipelines compiled, the k-NN table and RBF weights built now.
        const render::View v = view(*s, display, width, height, centre, 0.0);
        (void)mRenderer.renderFrame(std::span(&v, 1), std::span(&target, 1));
        (void)step.advance();
    }
    mRenderer.waitIdle();
    mRenderer.resetHistory();
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::string names;
    for (const std::string& spec : mScenes) {
        names += (names.empty() ? "" : ", ") + spec;
    }
    log::info("study: " + std::to_string(mine.size()) + " stimuli of " + names + " ready in " +
              std::to_string(static_cast<long>(ms)) + " ms");
}

nlohmann::json StudyStimuli::summary(const std::string& scene) const {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& [key, b] : mMethods) {
        if (!scene.empty() && std::get<0>(key) != scene) {
            continue;
        }
        nlohmann::json j{{"stimulus", std::get<1>(key)},
                         {"width", std::get<2>(key)},
                         {"height", std::get<3>(key)}};
        if (b.choice.method == study::Method::Foveated) {
            j["points"] = b.points;
        }
        list.push_back(std::move(j));
    }
    return list;
}

nlohmann::json StudyStimuli::summaryByScene() const {
    nlohmann::json byScene = nlohmann::json::object();
    for (const std::string& spec : mScenes) {
        byScene[spec] = summary(spec);
    }
    return byScene;
}

} // namespace gt::app
