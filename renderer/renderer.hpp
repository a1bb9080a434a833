#pragma once
// The frame pipeline every front end drives (`render`, `bench`, the desktop demo, the HMD path,
// OpenXR): the scene on the GPU, frames in flight, the temporal history, and renderFrame(), which
// builds one render graph holding every view of the frame — per view its foveation method, then
// the post chain (taa -> tonemap) and its output target — records it, submits it, and commits
// the history only once the submit succeeded.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "foveation_method.hpp"
#include "output_target.hpp"
#include "render_graph/frame_ring.hpp"
#include "render_graph/render_graph.hpp"
#include "scene/bvh.hpp"
#include "scene/dynamic_geometry.hpp"
#include "scene/gltf_loader.hpp"
#include "scene/scene.hpp"
#include "view.hpp"
#include "vk/context.hpp"

namespace gt::passes {
class TaaPass;
class TonemapPass;
class DenoisePass;
class LensPass;
} // namespace gt::passes

namespace gt::render {

struct RendererOptions {
    std::string scene = "builtin:market"; // builtin:NAME, FILE.gltf/.glb, cubemap:FILE
    bool validate = false;                // Khronos validation + synchronization validation
    // Frames the CPU may record ahead of the GPU; 0 picks: 2 on a GPU, 1 on a CPU driver such
    // as lavapipe, where the "GPU" shares the CPU's cores (two in flight measured no faster there
    // and added a frame of latency). A frame with a target that reads its result back (a PNG) is
    // always waited for.
    uint32_t framesInFlight = 1;
    vk::DeviceRequest deviceOverride; // automatic(): the best device
    scene::GltfLoadOptions sceneLoad; // what a glTF scene may ask of the loader
    // Which of an animated scene's animations play: "all", "none", a name or an index
    // (scene::chooseAnimation; an unknown one fails the constructor naming it). Scenes where
    // nothing moves ignore it.
    std::string animation = "all";
    // What a display needs of the Vulkan context: a window's extensions and surface, an OpenXR
    // runtime's hooks (its validation and device fields are taken from the two above).
    vk::ContextOptions display;
};

struct FrameOptions {
    bool graphviz = false; // FrameResult::dot
};

struct ViewResult {
    uint64_t rays = 0;
};

struct FrameResult {
    uint64_t number = 0;
    // The frame's GPU times per pass, when it was waited for (a readback target, or one frame
    // in flight); otherwise see Renderer::takeCompleted().
    std::optional<rg::FrameTimings> timings;
    std::string dot;     // Graphviz of the compiled graph, when asked for
    double wallMs = 0.0; // build + record + submit (+ wait + readback when waited for)
    std::vector<ViewResult> views;
};

class Renderer {
public:
    explicit Renderer(const RendererOptions& options);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    [[nodiscard]] vk::Context& context() noexcept;
    [[nodiscard]] const scene::Scene& scene() const noexcept;
    [[nodiscard]] const scene::BvhBuildStats& bvhStats() const noexcept;
    [[nodiscard]] const scene::Bvh& bvh() const noexcept { return *mBvh; }
    // Triangles of each geometric LOD level (one level for a scene without subdivision cages;
    // scene() and bvh() are level 0, the full detail).
    [[nodiscard]] std::vector<std::size_t> lodTriangles() const;
    [[nodiscard]] double loadMs() const noexcept { return mLoadMs; }
    [[nodiscard]] double bvhMs() const noexcept { return mBvhMs; }
    // For constructing foveation methods on this renderer's device and scene.
    [[nodiscard]] MethodContext methodContext() const noexcept;

    // Further scenes on the same device, each with its BVH, geometric LODs and GPU scene: a
    // method built with methodContext(id) traces scene `id`, so one frame's views (or
    // consecutive frames) may show different scenes. Scene 0 is RendererOptions::scene.
    using SceneId = std::size_t;
    SceneId addScene(const std::string& spec, const scene::GltfLoadOptions& load = {});
    [[nodiscard]] std::size_t sceneCount() const noexcept { return 1 + mMoreScenes.size(); }
    [[nodiscard]] const scene::Scene& scene(SceneId id) const;
    [[nodiscard]] MethodContext methodContext(SceneId id) const;

    // Scene time, in seconds, at which every animated scene is posed for the frames that follow
    // (render's frame clock, real time in the demo, the runtime's predicted display time in
    // xr). The pose of the frame before is where each hit's motion starts; the first call, and
    // a call going back in time, pose without motion. Scenes where nothing moves ignore it.
    void setSceneTime(double seconds);
    [[nodiscard]] double sceneTime() const noexcept { return mSceneTime; }
    // Whether some scene moves (a glTF animation, skin or morph target).
    [[nodiscard]] bool animated() const noexcept;
    // The scene's camera at the current scene time: the file's camera, moved by its node's
    // animation when it has one.
    [[nodiscard]] scene::Camera sceneCamera(SceneId id = 0) const;
    // The two-level part of scene `id` (null where nothing moves).
    [[nodiscard]] const scene::DynamicGeometry* dynamicGeometry(SceneId id = 0) const;

    // One frame of every view in one graph. `targets[i]` receives view i (the same count).
    // Throws gt::Error (the history is then left as it was: the next frame reads the same).
    FrameResult renderFrame(std::span<const View> views, std::span<OutputTarget* const> targets,
                            const FrameOptions& options = {});

    // Drops the temporal history of one view (by name) or of all views: the next frame starts
    // afresh (a camera cut, a saccade the caller knows of).
    void resetHistory(const std::string& view);
    void resetHistory();
    // Frames finished since the last call, with their GPU times (frames in flight).
    [[nodiscard]] std::vector<rg::CompletedFrame> takeCompleted();
    void waitIdle();
    [[nodiscard]] uint32_t framesInFlight() const noexcept;
    // Device memory of the views' frame images: their temporal histories and the transient
    // images of every frame in flight (not the methods' buffers and tables, nor the scene's);
    // of `extent` only, where given (a view's own size, apart from a method's coarser grids).
    [[nodiscard]] VkDeviceSize
    frameImageBytes(std::optional<VkExtent2D> extent = {}) const noexcept;

private:
    struct ViewHistory {
        shaders::trace::CameraPush camera{};
        glm::vec2 gaze{};
        bool valid = false;
        uint32_t samples = 0; // frames the TAA history holds
        bool pooled = false;  // TAA wrote the weight sums of a support too (taa.glsl)
        bool motion = false;  // and the signatures of a scene that moves
    };
    struct LoadedScene;
    // What each view's TAA leaves for the next frame, committed once the frame is submitted.
    using HistoryUpdates = std::vector<std::pair<std::string, ViewHistory>>;
    void runWarmUp(const WarmUp& warm);
    // One view's passes: its method's radiance, TAA, tone mapping, lens, and its target's output.
    void addView(rg::RenderGraph& graph, const View& v, OutputTarget& target,
                 HistoryUpdates& nextHistory);
    // The view's TAA over `made`, with its histories (colour, support weights, signatures).
    rg::TextureId addTaa(rg::RenderGraph& graph, const View& v, const MethodImage& made,
                         const shaders::trace::CameraPush& camera, HistoryUpdates& nextHistory);
    // Scene `id`'s two-level part and its GPU scene (null, null where nothing moves).
    std::pair<scene::DynamicGeometry*, trace::GpuScene*> moving(SceneId id) const;

    double mLoadMs = 0.0, mBvhMs = 0.0;
    double mSceneTime = 0.0;
    bool mScenePosed = false; // setSceneTime() was called: later calls carry motion
    std::string mAnimation;   // RendererOptions::animation, for scenes added later
    scene::Scene mScene;
    std::optional<scene::Bvh> mBvh;
    std::vector<std::pair<scene::Scene, scene::Bvh>> mCoarser; // LOD levels 1..
    std::unique_ptr<vk::Context> mCtx;
    std::unique_ptr<scene::DynamicGeometry> mDynamic; // scene 0's, when it moves
    std::unique_ptr<trace::GpuScene> mGpuScene;
    std::unique_ptr<passes::TaaPass> mTaa;
    std::unique_ptr<passes::TonemapPass> mTonemap;
    std::unique_ptr<passes::DenoisePass> mDenoise;
    std::unique_ptr<passes::LensPass> mLens;
    std::unique_ptr<rg::FrameRing> mRing;
    std::unique_ptr<rg::HistoryPool> mHistory;
    std::map<std::string, ViewHistory> mViewHistory;
    std::vector<std::unique_ptr<LoadedScene>> mMoreScenes; // scenes 1..: released before mCtx
};

} // namespace gt::render
