#include "xr_session.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/log.hpp"
#include "xr_error.hpp"

namespace gt::xr {

namespace {

// sRGB formats first: the runtime then reads the image as display-referred, as gazetrace's
// tonemapped output is. UNORM ones are taken too (the output target writes linear values there).
constexpr std::array<VkFormat, 4> kFormats = {VK_FORMAT_R8G8B8A8_SRGB, VK_FORMAT_B8G8R8A8_SRGB,
                                              VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_UNORM};

// How long one wait for a swapchain image may take before it counts as a runtime that hangs.
constexpr XrDuration kImageWaitNs = 2'000'000'000;

XrPosef identityPose() {
    XrPosef p{};
    p.orientation.w = 1.0f;
    return p;
}

XrSpace createReferenceSpace(XrSession session, XrReferenceSpaceType type) {
    XrReferenceSpaceCreateInfo info{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
    info.referenceSpaceType = type;
    info.poseInReferenceSpace = identityPose();
    XrSpace space = XR_NULL_HANDLE;
    GT_XR_CHECK(xrCreateReferenceSpace(session, &info, &space));
    return space;
}

} // namespace

Session::Session(const Runtime& runtime, vk::Context& ctx, const SessionOptions& options)
    : mRuntime(runtime), mCtx(ctx) {
    const auto scope = mCtx.runtimeCalls();
    XrGraphicsBindingVulkan2KHR binding{XR_TYPE_GRAPHICS_BINDING_VULKAN2_KHR};
    binding.instance = ctx.instance();
    binding.physicalDevice = ctx.physicalDevice();
    binding.device = ctx.device();
    binding.queueFamilyIndex = ctx.queueFamily();
    binding.queueIndex = 0;
    XrSessionCreateInfo info{XR_TYPE_SESSION_CREATE_INFO};
    info.next = &binding;
    info.systemId = runtime.system();
    GT_XR_CHECK(xrCreateSession(runtime.instance(), &info, &mSession));
    try {
        uint32_t n = 0;
        GT_XR_CHECK(xrEnumerateReferenceSpaces(mSession, 0, &n, nullptr));
        std::vector<XrReferenceSpaceType> spaces(n);
        GT_XR_CHECK(xrEnumerateReferenceSpaces(mSession, n, &n, spaces.data()));
        const bool stage =
            options.stageSpace &&
            std::find(spaces.begin(), spaces.end(), XR_REFERENCE_SPACE_TYPE_STAGE) != spaces.end();
        if (options.stageSpace && !stage) {
            log::warn("xr: the runtime offers no STAGE space; using LOCAL");
        }
        mAppSpace = createReferenceSpace(mSession, stage ? XR_REFERENCE_SPACE_TYPE_STAGE
                                                         : XR_REFERENCE_SPACE_TYPE_LOCAL);
        mSpaceName = stage ? "STAGE" : "LOCAL";
        mViewSpace = createReferenceSpace(mSession, XR_REFERENCE_SPACE_TYPE_VIEW);

        GT_XR_CHECK(xrEnumerateEnvironmentBlendModes(runtime.instance(), runtime.system(),
                                                     XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 0,
                                                     &n, nullptr));
        std::vector<XrEnvironmentBlendMode> modes(n);
        GT_XR_CHECK(xrEnumerateEnvironmentBlendModes(runtime.instance(), runtime.system(),
                                                     XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, n,
                                                     &n, modes.data()));
        if (modes.empty()) {
            throw Error("the OpenXR runtime offers no environment blend mode");
        }
        mBlendMode =
            std::find(modes.begin(), modes.end(), XR_ENVIRONMENT_BLEND_MODE_OPAQUE) != modes.end()
                ? XR_ENVIRONMENT_BLEND_MODE_OPAQUE
                : modes.front();
        createSwapchains(options);
    } catch (...) {
        release();
        throw;
    }
}

void Session::createSwapchains(const SessionOptions& options) {
    uint32_t n = 0;
    GT_XR_CHECK(xrEnumerateViewConfigurationViews(mRuntime.instance(), mRuntime.system(),
                                                  XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 0, &n,
                                                  nullptr));
    std::vector<XrViewConfigurationView> views(n, {XR_TYPE_VIEW_CONFIGURATION_VIEW});
    GT_XR_CHECK(xrEnumerateViewConfigurationViews(mRuntime.instance(), mRuntime.system(),
                                                  XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, n, &n,
                                                  views.data()));
    if (n != 2) {
        throw Error("the OpenXR runtime's stereo view configuration has " + std::to_string(n) +
                    " views, not 2");
    }
    GT_XR_CHECK(xrEnumerateSwapchainFormats(mSession, 0, &n, nullptr));
    std::vector<int64_t> formats(n);
    GT_XR_CHECK(xrEnumerateSwapchainFormats(mSession, n, &n, formats.data()));
    for (const VkFormat f : kFormats) {
        if (std::find(formats.begin(), formats.end(), static_cast<int64_t>(f)) != formats.end()) {
            mFormat = f;
            break;
        }
    }
    if (mFormat == VK_FORMAT_UNDEFINED) {
        std::string offered;
        for (const int64_t f : formats) {
            offered += (offered.empty() ? "" : ", ") + std::to_string(f);
        }
        throw Error("the OpenXR runtime offers no 8-bit RGBA swapchain format gazetrace can "
                    "write (it needs VkFormat 43, 50, 37 or 44; offered: " +
                    offered + ")");
    }
    for (uint32_t e = 0; e < 2; ++e) {
        Eye& eye = mEyes[e];
        const XrViewConfigurationView& v = views[e];
        eye.recommended = {v.recommendedImageRectWidth, v.recommendedImageRectHeight};
        double scale = options.resolutionScale;
        if (options.maxWidth != 0) {
            scale = std::min(scale, options.maxWidth / double(v.recommendedImageRectWidth));
        }
        if (options.maxHeight != 0) {
            scale = std::min(scale, options.maxHeight / double(v.recommendedImageRectHeight));
        }
        const auto scaled = [&](uint32_t rec, uint32_t max) {
            const double s = std::round(rec * scale);
            return std::clamp<uint32_t>(static_cast<uint32_t>(std::max(s, 16.0)), 16u,
                                        std::max(max, 16u));
        };
        eye.extent = {scaled(v.recommendedImageRectWidth, v.maxImageRectWidth),
                      scaled(v.recommendedImageRectHeight, v.maxImageRectHeight)};
        XrSwapchainCreateInfo info{XR_TYPE_SWAPCHAIN_CREATE_INFO};
        // Written by a blit (transfer), read back for --screenshot-eye (transfer), then read by
        // the runtime's compositor.
        info.usageFlags = XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT |
                          XR_SWAPCHAIN_USAGE_TRANSFER_SRC_BIT |
                          XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_SAMPLED_BIT;
        info.format = static_cast<int64_t>(mFormat);
        info.sampleCount = 1;
        info.width = eye.extent.width;
        info.height = eye.extent.height;
        info.faceCount = 1;
        info.arraySize = 1;
        info.mipCount = 1;
        GT_XR_CHECK(xrCreateSwapchain(mSession, &info, &eye.swapchain));
        GT_XR_CHECK(xrEnumerateSwapchainImages(eye.swapchain, 0, &n, nullptr));
        std::vector<XrSwapchainImageVulkan2KHR> images(n, {XR_TYPE_SWAPCHAIN_IMAGE_VULKAN2_KHR});
        GT_XR_CHECK(xrEnumerateSwapchainImages(
            eye.swapchain, n, &n, reinterpret_cast<XrSwapchainImageBaseHeader*>(images.data())));
        for (const auto& img : images) {
            eye.images.push_back(img.image);
        }
    }
}

Session::~Session() {
    const auto scope = mCtx.runtimeCalls();
    release();
}

void Session::release() noexcept {
    // Errors are ignored here: a runtime that went away answers every call with one.
    for (Eye& eye : mEyes) {
        if (eye.swapchain != XR_NULL_HANDLE) {
            xrDestroySwapchain(eye.swapchain);
        }
        eye.swapchain = XR_NULL_HANDLE;
    }
    if (mViewSpace != XR_NULL_HANDLE) {
        xrDestroySpace(mViewSpace);
    }
    if (mAppSpace != XR_NULL_HANDLE) {
        xrDestroySpace(mAppSpace);
    }
    if (mSession != XR_NULL_HANDLE) {
        xrDestroySession(mSession);
    }
    mViewSpace = mAppSpace = XR_NULL_HANDLE;
    mSession = XR_NULL_HANDLE;
}

bool Session::pollEvents() {
    const auto scope = mCtx.runtimeCalls();
    for (;;) {
        XrEventDataBuffer event{XR_TYPE_EVENT_DATA_BUFFER};
        const XrResult r = xrPollEvent(mRuntime.instance(), &event);
        if (r == XR_EVENT_UNAVAILABLE) {
            return true;
        }
        GT_XR_CHECK(r);
        if (event.type == XR_TYPE_EVENT_DATA_INSTANCE_LOSS_PENDING) {
            throw Error("the OpenXR runtime is shutting down (instance loss pending)");
        }
        if (event.type == XR_TYPE_EVENT_DATA_EVENTS_LOST) {
            log::warn("xr: the runtime dropped events");
            continue;
        }
        if (event.type != XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) {
            continue;
        }
        const auto& changed = reinterpret_cast<const XrEventDataSessionStateChanged&>(event);
        log::info("xr: session " + stateName(changed.state));
        switch (mLifecycle.onStateChanged(changed.state)) {
        case LifecycleAction::BeginSession: {
            XrSessionBeginInfo begin{XR_TYPE_SESSION_BEGIN_INFO};
            begin.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
            GT_XR_CHECK(xrBeginSession(mSession, &begin));
            mLifecycle.began();
            break;
        }
        case LifecycleAction::EndSession:
            GT_XR_CHECK(xrEndSession(mSession));
            mLifecycle.ended();
            break;
        case LifecycleAction::Exit:
            return false;
        case LifecycleAction::Lost:
            throw Error("the OpenXR runtime lost the session (LOSS_PENDING): the headset or its "
                        "service went away");
        case LifecycleAction::None:
            break;
        }
    }
}

void Session::requestExit() {
    const auto scope = mCtx.runtimeCalls();
    if (mLifecycle.isExitRequested()) {
        return;
    }
    mLifecycle.exitRequested();
    if (mLifecycle.running()) {
        GT_XR_CHECK(xrRequestExitSession(mSession));
    }
}

FrameInfo Session::beginFrame() {
    const auto scope = mCtx.runtimeCalls();
    FrameInfo f;
    XrFrameWaitInfo wait{XR_TYPE_FRAME_WAIT_INFO};
    XrFrameState state{XR_TYPE_FRAME_STATE};
    GT_XR_CHECK(xrWaitFrame(mSession, &wait, &state));
    XrFrameBeginInfo begin{XR_TYPE_FRAME_BEGIN_INFO};
    GT_XR_CHECK(xrBeginFrame(mSession, &begin));
    f.displayTime = state.predictedDisplayTime;
    f.displayPeriod = state.predictedDisplayPeriod;
    f.shouldRender = state.shouldRender == XR_TRUE;
    if (!f.shouldRender) {
        return f;
    }
    const auto locate = [&](XrSpace space, std::array<XrView, 2>& out) {
        XrViewLocateInfo info{XR_TYPE_VIEW_LOCATE_INFO};
        info.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
        info.displayTime = f.displayTime;
        info.space = space;
        XrViewState vs{XR_TYPE_VIEW_STATE};
        out.fill({XR_TYPE_VIEW});
        uint32_t n = 0;
        GT_XR_CHECK(xrLocateViews(mSession, &info, &vs, 2, &n, out.data()));
        constexpr XrViewStateFlags both =
            XR_VIEW_STATE_ORIENTATION_VALID_BIT | XR_VIEW_STATE_POSITION_VALID_BIT;
        return n == 2 && (vs.viewStateFlags & both) == both;
    };
    f.posesValid = locate(mAppSpace, f.views);
    f.posesValid = locate(mViewSpace, f.headViews) && f.posesValid;
    return f;
}

EyeImage Session::acquire(uint32_t eye) {
    const auto scope = mCtx.runtimeCalls();
    Eye& e = mEyes.at(eye);
    XrSwapchainImageAcquireInfo info{XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO};
    GT_XR_CHECK(xrAcquireSwapchainImage(e.swapchain, &info, &e.acquired));
    XrSwapchainImageWaitInfo wait{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
    wait.timeout = kImageWaitNs;
    const XrResult r = xrWaitSwapchainImage(e.swapchain, &wait);
    if (r == XR_TIMEOUT_EXPIRED) {
        throw Error("the OpenXR runtime did not hand back a swapchain image within 2 s");
    }
    GT_XR_CHECK(r);
    if (e.acquired >= e.images.size()) {
        throw Error("the OpenXR runtime gave an unknown image");
    }
    return {e.images[e.acquired], mFormat, e.extent};
}

void Session::release(uint32_t eye) {
    const auto scope = mCtx.runtimeCalls();
    Eye& e = mEyes.at(eye);
    XrSwapchainImageReleaseInfo info{XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO};
    GT_XR_CHECK(xrReleaseSwapchainImage(e.swapchain, &info));
    e.acquired = ~0u;
}

void Session::endFrame(const FrameInfo& frame, bool layer) {
    const auto scope = mCtx.runtimeCalls();
    std::array<XrCompositionLayerProjectionView, 2> views{};
    XrCompositionLayerProjection projection{XR_TYPE_COMPOSITION_LAYER_PROJECTION};
    const XrCompositionLayerBaseHeader* layers[1] = {
        reinterpret_cast<const XrCompositionLayerBaseHeader*>(&projection)};
    for (uint32_t e = 0; e < 2; ++e) {
        XrCompositionLayerProjectionView& v = views[e];
        v = {XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW};
        v.pose = frame.views[e].pose;
        v.fov = frame.views[e].fov;
        v.subImage.swapchain = mEyes[e].swapchain;
        v.subImage.imageRect.extent = {static_cast<int32_t>(mEyes[e].extent.width),
                                       static_cast<int32_t>(mEyes[e].extent.height)};
        v.subImage.imageArrayIndex = 0;
    }
    projection.space = mAppSpace;
    projection.viewCount = 2;
    projection.views = views.data();
    XrFrameEndInfo end{XR_TYPE_FRAME_END_INFO};
    end.displayTime = frame.displayTime;
    end.environmentBlendMode = mBlendMode;
    end.layerCount = layer ? 1 : 0;
    end.layers = layer ? layers : nullptr;
    GT_XR_CHECK(xrEndFrame(mSession, &end));
}

} // namespace gt::xr
