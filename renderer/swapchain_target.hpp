#pragma once
// A window's swapchain image as a frame's output. Each view's display-referred image is blitted
// (scaled, linear filter) into its place on the image — the whole image for a desktop window, one
// half each for the two eyes of a side-by-side HMD frame. Then an overlay may draw on top, a
// screenshot may copy the result to host memory, and the image ends in PRESENT_SRC (a sink).
// The frame's submit waits for the image's acquire and signals its present semaphore.
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "output_target.hpp"
#include "vk/swapchain.hpp"

namespace gt::render {

class SwapchainTarget final : public OutputTarget {
public:
    explicit SwapchainTarget(vk::Context& ctx) : mScreenshotCopy(ctx) {}
    // The image this frame draws into (acquired by the caller, who presents it afterwards).
    void setImage(const vk::Swapchain::Image& image, VkFormat format, VkExtent2D extent);
    // Where the view named `view` goes, in swapchain pixels; unplaced views fill the image.
    void place(const std::string& view, VkRect2D rect);
    // Draws over the composed image inside the frame (the overlay): reads and writes `image`,
    // returns the new version.
    using Overlay = std::function<rg::TextureId(rg::RenderGraph&, rg::TextureId image)>;
    void setOverlay(Overlay overlay) { mOverlay = std::move(overlay); }
    // Copies the next frame's presented image to host memory (RGBA8, rows top first).
    void requestScreenshot() { mScreenshotWanted = true; }
    [[nodiscard]] const std::optional<std::vector<uint8_t>>& screenshot() const noexcept {
        return mScreenshot;
    }
    [[nodiscard]] VkExtent2D extent() const noexcept { return mExtent; }

    void beginFrame(rg::RenderGraph& graph) override;
    void addOutput(rg::RenderGraph& graph, rg::TextureId image, const View& view) override;
    void endFrame(rg::RenderGraph& graph) override;
    void addSync(rg::SubmitSync& sync) override;
    [[nodiscard]] bool waitsForFrame() const noexcept override { return mScreenshotWanted; }
    void frameFinished() override;

private:
    std::optional<vk::Swapchain::Image> mImage;
    VkFormat mFormat = VK_FORMAT_UNDEFINED;
    VkExtent2D mExtent{};
    std::map<std::string, VkRect2D> mPlaces;
    Overlay mOverlay;
    rg::TextureId mTarget;
    bool mScreenshotWanted = false;
    HostImageCopy mScreenshotCopy;
    std::optional<std::vector<uint8_t>> mScreenshot;
};

} // namespace gt::render
