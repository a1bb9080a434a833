#pragma once
// The window's swapchain on the context's surface: images, their views, the semaphores that
// order acquire -> render -> present, and recreation when the surface changes (resize, out of
// date). FIFO is always offered; MAILBOX and IMMEDIATE are used when asked for and offered.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace gt::vk {

class Context;

enum class PresentMode { Fifo, Mailbox, Immediate };
[[nodiscard]] const char* toString(VkPresentModeKHR mode) noexcept;

class Swapchain {
public:
    // `size` is the window's framebuffer size in pixels (the surface's own extent wins when it
    // has one). Throws when the surface offers no usable format.
    Swapchain(Context& ctx, VkExtent2D size, PresentMode preferred);
    ~Swapchain();
    Swapchain(const Swapchain&) = delete;
    Swapchain& operator=(const Swapchain&) = delete;

    struct Image {
        uint32_t index = 0;
        VkImage image = VK_NULL_HANDLE;
        VkImageView view = VK_NULL_HANDLE;
        VkSemaphore acquired = VK_NULL_HANDLE; // the frame's submit waits for it
        VkSemaphore rendered = VK_NULL_HANDLE; // the frame's submit signals it; present waits
    };
    // The next image, or empty when the swapchain is out of date (call recreate()).
    [[nodiscard]] std::optional<Image> acquire();
    // Presents; false when the swapchain is out of date or suboptimal (call recreate()).
    [[nodiscard]] bool present(const Image& image);
    // After a resize: waits for the device, then builds a new swapchain from the old one.
    void recreate(VkExtent2D size);

    [[nodiscard]] VkFormat format() const noexcept { return mFormat; }
    [[nodiscard]] VkExtent2D extent() const noexcept { return mExtent; }
    [[nodiscard]] VkPresentModeKHR presentMode() const noexcept { return mMode; }
    [[nodiscard]] uint32_t imageCount() const noexcept {
        return static_cast<uint32_t>(mImages.size());
    }

private:
    void create(VkExtent2D size);
    void destroyImages() noexcept;

    Context& mCtx;
    PresentMode mPreferred;
    VkSwapchainKHR mSwapchain = VK_NULL_HANDLE;
    VkFormat mFormat = VK_FORMAT_UNDEFINED;
    VkExtent2D mExtent{};
    VkPresentModeKHR mMode = VK_PRESENT_MODE_FIFO_KHR;
    std::vector<VkImage> mImages;
    std::vector<VkImageView> mViews;
    std::vector<VkSemaphore> mRendered; // one per image
    std::vector<VkSemaphore> mAcquired; // a ring, one more than images
    uint32_t mNextAcquire = 0;
};

} // namespace gt::vk
