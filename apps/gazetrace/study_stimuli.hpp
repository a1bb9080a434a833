#pragma once
// A perception study's stimuli (study::Stimulus, typed values) as the renderer's methods, for
// every front end of `gazetrace study` (the window, headless runs, OpenXR): one foveation method
// per distinct stimulus and view size, every one of them built before the first trial
// (prepare: the point set of every level loaded from the cache or generated, its neighbour
// index, its k-NN table and its pipelines run once), so no trial waits for one; and each
// scene's camera at a time into an interval.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "foveation/contrast_sensitivity.hpp"
#include "renderer.hpp"
#include "scene/camera_path.hpp"
#include "settings.hpp"
#include "stimulus.hpp"

namespace gt::app {

// Where the stimuli are seen: the display the thesis's point sets are built for (a window on
// the desktop screen, an HMD eye), and the screen Guenter et al. 2012's layers are sized on
// (empty: each view's own frustum is the eye's field of view, as for an HMD eye).
struct StimulusDisplay {
    foveation::DisplayProfile pointSets;
    std::optional<foveation::DisplayProfile> layers;
    bool displaySpace = false; // point sets laid on an HMD's panel (PointSetSettings)
};

// The desktop path's display for a width x height view: a window on the desktop screen (the
// same pixels per degree as render and demo use).
[[nodiscard]] StimulusDisplay desktopStimulusDisplay(uint32_t width, uint32_t height);

// The renderer's settings for one stimulus on `display`, point sets cached in `cacheDir`.
[[nodiscard]] render::RenderSettings renderSettingsOf(const study::RenderChoice& choice,
                                                      const StimulusDisplay& display,
                                                      const std::filesystem::path& cacheDir);

// A stimulus's settings in the render command's words ("foveated scale 1.4 rays-per-point 1
// interp nn"), for logs and summaries.
[[nodiscard]] std::string describe(const study::RenderChoice& choice);

// The scene specs the stimuli show, each once, in the order first shown.
[[nodiscard]] std::vector<std::string> scenesOf(std::span<const study::Stimulus> stimuli);

// The methods of one renderer and its scenes (`scenes[i]`, the spec its scene i was loaded
// from), each method built against the scene its stimulus shows. Views of a stimulus are
// rendered with view() (or method() and post()); a view of another size than prepared builds
// its method on first use.
class StudyStimuli {
public:
    StudyStimuli(render::Renderer& renderer, std::vector<std::string> scenes,
                 const std::string& cacheDir);
    ~StudyStimuli();
    StudyStimuli(const StudyStimuli&) = delete;
    StudyStimuli& operator=(const StudyStimuli&) = delete;

    // Builds the method of every stimulus of this renderer's scenes (the others are left to
    // theirs) for
    // width x height views on `display`, and renders one frame of each (nothing shown, the
    // history dropped after), so the first trial's frames cost what every later one does.
    // Checks every stimulus's camera and camera path too (ArgumentError naming it).
    void prepare(std::span<const study::Stimulus> stimuli, const StimulusDisplay& display,
                 uint32_t width, uint32_t height);
    // The method of `stimulus` for a width x height view, its settings set.
    [[nodiscard]] render::FoveationMethod& method(const study::Stimulus& stimulus,
                                                  const StimulusDisplay& display, uint32_t width,
                                                  uint32_t height);
    [[nodiscard]] static render::PostSettings post(const study::Stimulus& stimulus);
    // The camera `ms` into an interval of `scene`: its camera path from its start, its fixed
    // camera, or the scene's own.
    [[nodiscard]] scene::Camera camera(const study::SceneChoice& scene, double ms);
    // A width x height view of `stimulus` with the gaze at `gazePx` at `ms` into the interval.
    [[nodiscard]] render::View view(const study::Stimulus& stimulus, const StimulusDisplay& display,
                                    uint32_t width, uint32_t height, glm::vec2 gazePx, double ms);

    // Every prepared stimulus (of `scene`; empty: of all scenes): its settings and, for point
    // sets, the set's points.
    [[nodiscard]] nlohmann::json summary(const std::string& scene = {}) const;
    // summary() of each scene, keyed by its spec.
    [[nodiscard]] nlohmann::json summaryByScene() const;
    [[nodiscard]] std::size_t methodCount() const noexcept { return mMethods.size(); }
    [[nodiscard]] render::Renderer& renderer() noexcept { return mRenderer; }
    // The first scene's spec (scene 0 of the renderer).
    [[nodiscard]] const std::string& scene() const noexcept { return mScenes.front(); }
    [[nodiscard]] const std::vector<std::string>& scenes() const noexcept { return mScenes; }
    // The renderer's scene loaded from `spec` (Error when it holds none).
    [[nodiscard]] render::Renderer::SceneId sceneId(const std::string& spec) const;
    // The exposure of the scene `stimulus` shows.
    [[nodiscard]] float exposure(const study::Stimulus& stimulus) const;

private:
    // The scene's spec, describe(), width, height.
    using Key = std::tuple<std::string, std::string, uint32_t, uint32_t>;
    struct Built {
        study::RenderChoice choice;
        std::unique_ptr<render::FoveationMethod> method;
        std::size_t points = 0; // point sets: the set's size
    };

    render::Renderer& mRenderer;
    std::vector<std::string> mScenes;
    std::filesystem::path mCacheDir;
    std::map<Key, Built> mMethods;
    std::map<std::string, scene::CameraPath> mPaths;
};

} // namespace gt::app
