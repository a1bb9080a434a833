#include "vk/swapchain.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "vk/context.hpp"

namespace gt::vk {

const char* toString(VkPresentModeKHR mode) noexcept {
    switch (mode) {
    case VK_PRESENT_MODE_FIFO_KHR:
        return "fifo";
    case VK_PRESENT_MODE_MAILBOX_KHR:
        return "mailbox";
    case VK_PRESENT_MODE_IMMEDIATE_KHR:
        return "immediate";
    case VK_PRESENT_MODE_FIFO_RELAXED_KHR:
        return "fifo_relaxed";
    default:
        return "other";
    }
}

Swapchain::Swapchain(Context& ctx, VkExtent2D size, PresentMode preferred)
    : mCtx(ctx), mPreferred(preferred) {
    if (ctx.surface() == VK_NULL_HANDLE) throw Error("swapchain without a window surface");
    try {
        create(size);
    } catch (...) {
        destroyImages();
        if (mSwapchain != VK_NULL_HANDLE) vkDestroySwapchainKHR(ctx.device(), mSwapchain, nullptr);
        throw;
    }
}

Swapchain::~Swapchain() {
    vkDeviceWaitIdle(mCtx.device());
    destroyImages();
    if (mSwapchain != VK_NULL_HANDLE) vkDestroySwapchainKHR(mCtx.device(), mSwapchain, nullptr);
}

void Swapchain::destroyImages() noexcept {
    const VkDevice d = mCtx.device();
    for (VkImageView v : mViews)
        vkDestroyImageView(d, v, nullptr);
    for (VkSemaphore s : mRendered)
        vkDestroySemaphore(d, s, nullptr);
    for (VkSemaphore s : mAcquired)
        vkDestroySemaphore(d, s, nullptr);
    mViews.clear();
    mRendered.clear();
    mAcquired.clear();
    mImages.clear();
}

void Swapchain::create(VkExtent2D size) {
    const VkPhysicalDevice pd = mCtx.physicalDevice();
    const VkSurfaceKHR surface = mCtx.surface();
    VkSurfaceCapabilitiesKHR caps{};
    GT_VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(pd, surface, &caps));
    uint32_t n = 0;
    GT_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, nullptr));
    std::vector<VkSurfaceFormatKHR> formats(n);
    GT_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, formats.data()));
    // UNORM: the tone mapper already wrote sRGB-encoded values; a blit copies them unchanged.
    const auto fmt = std::find_if(formats.begin(), formats.end(), [](VkSurfaceFormatKHR f) {
        return (f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_UNORM) &&
               f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
    });
    if (fmt == formats.end()) {
        throw Error("the window surface offers no 8-bit UNORM sRGB format");
    }
    mFormat = fmt->format;
    GT_VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, nullptr));
    std::vector<VkPresentModeKHR> modes(n);
    GT_VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, modes.data()));
    const VkPresentModeKHR wanted = mPreferred == PresentMode::Mailbox ? VK_PRESENT_MODE_MAILBOX_KHR
                                    : mPreferred == PresentMode::Immediate
                                        ? VK_PRESENT_MODE_IMMEDIATE_KHR
                                        : VK_PRESENT_MODE_FIFO_KHR;
    mMode = std::find(modes.begin(), modes.end(), wanted) != modes.end()
                ? wanted
                : VK_PRESENT_MODE_FIFO_KHR; // always offered
    mExtent =
        caps.currentExtent.width != 0xFFFFFFFFu
            ? caps.currentExtent
            : VkExtent2D{
                  std::clamp(size.width, caps.minImageExtent.width, caps.maxImageExtent.width),
                  std::clamp(size.height, caps.minImageExtent.height, caps.maxImageExtent.height)};
    uint32_t count = std::max(caps.minImageCount + 1, 3u);
    if (caps.maxImageCount > 0) count = std::min(count, caps.maxImageCount);

    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = surface;
    info.minImageCount = count;
    info.imageFormat = mFormat;
    info.imageColorSpace = fmt->colorSpace;
    info.imageExtent = mExtent;
    info.imageArrayLayers = 1;
    // Blit target of the finished view, colour attachment of the overlay, copy source of a
    // screenshot.
    info.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    info.presentMode = mMode;
    info.clipped = VK_TRUE;
    info.oldSwapchain = mSwapchain;
    VkSwapchainKHR created = VK_NULL_HANDLE;
    GT_VK_CHECK(vkCreateSwapchainKHR(mCtx.device(), &info, nullptr, &created));
    if (mSwapchain != VK_NULL_HANDLE) vkDestroySwapchainKHR(mCtx.device(), mSwapchain, nullptr);
    mSwapchain = created;

    GT_VK_CHECK(vkGetSwapchainImagesKHR(mCtx.device(), mSwapchain, &n, nullptr));
    mImages.resize(n);
    GT_VK_CHECK(vkGetSwapchainImagesKHR(mCtx.device(), mSwapchain, &n, mImages.data()));
    for (uint32_t i = 0; i < n; ++i) {
        VkImageViewCreateInfo v{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        v.image = mImages[i];
        v.viewType = VK_IMAGE_VIEW_TYPE_2D;
        v.format = mFormat;
        v.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VkImageView view = VK_NULL_HANDLE;
        GT_VK_CHECK(vkCreateImageView(mCtx.device(), &v, nullptr, &view));
        mViews.push_back(view);
        mCtx.setName(VK_OBJECT_TYPE_IMAGE, reinterpret_cast<uint64_t>(mImages[i]),
                     "swapchain#" + std::to_string(i));
    }
    VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    for (uint32_t i = 0; i < n; ++i) {
        VkSemaphore s = VK_NULL_HANDLE;
        GT_VK_CHECK(vkCreateSemaphore(mCtx.device(), &si, nullptr, &s));
        mRendered.push_back(s);
    }
    for (uint32_t i = 0; i <= n; ++i) {
        VkSemaphore s = VK_NULL_HANDLE;
        GT_VK_CHECK(vkCreateSemaphore(mCtx.device(), &si, nullptr, &s));
        mAcquired.push_back(s);
    }
    mNextAcquire = 0;
}

void Swapchain::recreate(VkExtent2D size) {
    GT_VK_CHECK(vkDeviceWaitIdle(mCtx.device()));
    destroyImages();
    create(size);
}

std::optional<Swapchain::Image> Swapchain::acquire() {
    const VkSemaphore acquired = mAcquired[mNextAcquire];
    uint32_t index = 0;
    const VkResult r = vkAcquireNextImageKHR(mCtx.device(), mSwapchain, UINT64_MAX, acquired,
                                             VK_NULL_HANDLE, &index);
    if (r == VK_ERROR_OUT_OF_DATE_KHR) return std::nullopt;
    if (r == VK_ERROR_SURFACE_LOST_KHR) throw Error("the window's surface was lost");
    if (r != VK_SUBOPTIMAL_KHR) GT_VK_CHECK(r);
    mNextAcquire = (mNextAcquire + 1) % static_cast<uint32_t>(mAcquired.size());
    return Image{index, mImages[index], mViews[index], acquired, mRendered[index]};
}

bool Swapchain::present(const Image& image) {
    VkPresentInfoKHR info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    info.waitSemaphoreCount = 1;
    info.pWaitSemaphores = &image.rendered;
    info.swapchainCount = 1;
    info.pSwapchains = &mSwapchain;
    info.pImageIndices = &image.index;
    const VkResult r = vkQueuePresentKHR(mCtx.queue(), &info);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) return false;
    if (r == VK_ERROR_SURFACE_LOST_KHR) throw Error("the window's surface was lost");
    GT_VK_CHECK(r);
    return true;
}

} // namespace gt::vk
