#pragma once
// A view's finished image into an image someone else owns and hands over for one frame: an
// OpenXR swapchain image, acquired and waited for by the caller, who releases it after the frame
// was submitted. The display-referred image is copied bit for bit into an sRGB texture (pass
// `copy`) and blitted from there into the image, so sRGB and linear, RGBA and BGRA images all
// receive the right colours. The image ends in COLOR_ATTACHMENT_OPTIMAL, the layout OpenXR
// requires of a released Vulkan swapchain image. No semaphores: the runtime orders its own use
// of the image on the same queue.
#include <cstdint>
#include <optional>
#include <vector>

#include "output_target.hpp"

namespace gt::render {

struct ExternalImage {
    VkImage image = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkExtent2D extent{};
    uint32_t layer = 0; // array layer (an array swapchain: one layer per eye)
};

class ExternalImageTarget final : public OutputTarget {
public:
    explicit ExternalImageTarget(vk::Context& ctx) : mScreenshotCopy(ctx) {}
    // The image this frame writes; the view is scaled to fill it.
    void setImage(const ExternalImage& image) { mImage = image; }
    // Reads the next frame's image back after the view was written into it, as RGBA8
    // sRGB-encoded (whatever the image's format), the image's size.
    void requestScreenshot() { mScreenshotWanted = true; }
    [[nodiscard]] const std::optional<std::vector<uint8_t>>& screenshot() const noexcept {
        return mScreenshot;
    }

    void addOutput(rg::RenderGraph& graph, rg::TextureId image, const View& view) override;
    [[nodiscard]] bool waitsForFrame() const noexcept override { return mScreenshotWanted; }
    void frameFinished() override;

private:
    std::optional<ExternalImage> mImage;
    bool mScreenshotWanted = false;
    HostImageCopy mScreenshotCopy;
    VkFormat mScreenshotFormat = VK_FORMAT_UNDEFINED;
    std::optional<std::vector<uint8_t>> mScreenshot;
};

} // namespace gt::render
