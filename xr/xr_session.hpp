#pragma once
// One OpenXR session on gazetrace's Vulkan device: the life cycle (session_lifecycle.hpp), the
// reference spaces, one swapchain per eye of the primary stereo view configuration, and the
// frame calls (xrWaitFrame / xrBeginFrame / xrLocateViews / xrEndFrame with one projection layer).
// The renderer draws each eye into the image acquired from that eye's swapchain between
// beginFrame() and endFrame(). Every call into the runtime runs inside the context's
// runtimeCalls() scope: the validation messages its in-process compositor raises meanwhile are
// the runtime's, not gazetrace's.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "openxr.hpp"
#include "session_lifecycle.hpp"
#include "vk/context.hpp"
#include "xr_runtime.hpp"

namespace gt::xr {

struct SessionOptions {
    bool stageSpace = false;      // STAGE (floor-level origin) where offered, else LOCAL
    double resolutionScale = 1.0; // of the runtime's recommended eye image size
    // At most this size (the recommended size scaled down further, its aspect kept); 0: no limit.
    uint32_t maxWidth = 0, maxHeight = 0;
};

// One frame as the runtime paces it.
struct FrameInfo {
    XrTime displayTime = 0; // predicted display time of this frame
    XrDuration displayPeriod = 0;
    bool shouldRender = false;         // false while SYNCHRONIZED (frames are not shown)
    bool posesValid = false;           // both eyes' orientation and position are known
    std::array<XrView, 2> views{};     // each eye in the application's reference space
    std::array<XrView, 2> headViews{}; // each eye relative to the head (VIEW space)
};

struct EyeImage {
    VkImage image = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkExtent2D extent{};
};

class Session {
public:
    // `ctx` must be the context created through runtime.vulkanHooks(); both must outlive this.
    Session(const Runtime& runtime, vk::Context& ctx, const SessionOptions& options);
    ~Session();
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    // Reads the runtime's events and acts on state changes (xrBeginSession on READY,
    // xrEndSession on STOPPING). Returns false once the session is over (EXITING); throws
    // gt::Error when the runtime lost it.
    bool pollEvents();
    [[nodiscard]] bool running() const noexcept { return mLifecycle.running(); }
    [[nodiscard]] const SessionLifecycle& lifecycle() const noexcept { return mLifecycle; }
    // Ask the runtime to end the session (it answers STOPPING, then EXITING).
    void requestExit();

    // xrWaitFrame, xrBeginFrame and both eyes' views at the predicted display time.
    [[nodiscard]] FrameInfo beginFrame();
    // The eye's next swapchain image, ready to be written (acquired and waited for).
    [[nodiscard]] EyeImage acquire(uint32_t eye);
    // After the frame that writes it was submitted.
    void release(uint32_t eye);
    // Ends the frame; with `layer` the two eyes go out as one projection layer.
    void endFrame(const FrameInfo& frame, bool layer);

    [[nodiscard]] XrSession handle() const noexcept { return mSession; }
    [[nodiscard]] const Runtime& runtime() const noexcept { return mRuntime; }
    [[nodiscard]] vk::Context& context() const noexcept { return mCtx; }
    [[nodiscard]] XrSpace appSpace() const noexcept { return mAppSpace; }
    [[nodiscard]] XrSpace viewSpace() const noexcept { return mViewSpace; }
    [[nodiscard]] const std::string& spaceName() const noexcept { return mSpaceName; }
    [[nodiscard]] VkExtent2D eyeExtent(uint32_t eye) const { return mEyes.at(eye).extent; }
    [[nodiscard]] VkExtent2D recommendedExtent(uint32_t eye) const {
        return mEyes.at(eye).recommended;
    }
    [[nodiscard]] VkFormat format() const noexcept { return mFormat; }

private:
    struct Eye {
        XrSwapchain swapchain = XR_NULL_HANDLE;
        std::vector<VkImage> images;
        VkExtent2D extent{}, recommended{};
        uint32_t acquired = ~0u;
    };
    void createSwapchains(const SessionOptions& options);
    void release() noexcept;

    const Runtime& mRuntime;
    vk::Context& mCtx;
    XrSession mSession = XR_NULL_HANDLE;
    XrSpace mAppSpace = XR_NULL_HANDLE, mViewSpace = XR_NULL_HANDLE;
    std::string mSpaceName;
    XrEnvironmentBlendMode mBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
    VkFormat mFormat = VK_FORMAT_UNDEFINED;
    std::array<Eye, 2> mEyes;
    SessionLifecycle mLifecycle;
};

} // namespace gt::xr
