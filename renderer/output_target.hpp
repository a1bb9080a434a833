#pragma once
// Where a view's finished image goes: back to the CPU (a PNG), into a window's swapchain image,
// into an OpenXR swapchain image. A target adds the passes that take the view's display-referred
// image (RGBA8 sRGB, the view's size) out of the frame and marks what it wrote as a sink, so the
// graph keeps the chain alive and leaves the image in the state its consumer expects.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "render_graph/frame_ring.hpp"
#include "render_graph/render_graph.hpp"
#include "vk/resources.hpp"

namespace gt::render {

struct View;

// A host-visible copy of a texture (RGBA8), recorded inside a frame and read once the frame
// finished: a PNG's pixels, a window's or an OpenXR eye's screenshot.
class HostImageCopy {
public:
    explicit HostImageCopy(vk::Context& ctx) : mCtx(ctx) {}
    // Adds pass "readback.NAME" copying `image` (width x height) into "NAME.host".
    void add(rg::RenderGraph& graph, const std::string& name, rg::TextureId image, uint32_t width,
             uint32_t height);
    [[nodiscard]] bool recorded() const noexcept { return mHost.has_value(); }
    // Rows top first, tightly packed; call only after the frame finished.
    [[nodiscard]] std::vector<uint8_t> download() const;

private:
    vk::Context& mCtx;
    std::optional<vk::Buffer> mHost;
};

class OutputTarget {
public:
    virtual ~OutputTarget() = default;
    // Once per frame for each distinct target, before the views and after them, outside any
    // view's scope (one window target can take both eyes of a side-by-side frame).
    virtual void beginFrame(rg::RenderGraph& graph) { (void)graph; }
    virtual void endFrame(rg::RenderGraph& graph) { (void)graph; }
    // Called inside the view's graph scope.
    virtual void addOutput(rg::RenderGraph& graph, rg::TextureId image, const View& view) = 0;
    // Semaphores the frame's submit waits for and signals (a swapchain's acquire and present).
    virtual void addSync(rg::SubmitSync& sync) { (void)sync; }
    // Whether renderFrame must wait for the frame before returning (the CPU reads its output).
    [[nodiscard]] virtual bool waitsForFrame() const noexcept { return false; }
    // After the frame finished on the GPU (only for targets that wait for it).
    virtual void frameFinished() {}
};

// Copies the image into host memory; pixels() holds it once renderFrame returns.
class ReadbackTarget final : public OutputTarget {
public:
    explicit ReadbackTarget(vk::Context& ctx) : mCopy(ctx) {}
    void addOutput(rg::RenderGraph& graph, rg::TextureId image, const View& view) override;
    [[nodiscard]] bool waitsForFrame() const noexcept override { return true; }
    void frameFinished() override;
    // RGBA8 sRGB, rows top first, tightly packed.
    [[nodiscard]] const std::vector<uint8_t>& pixels() const noexcept { return mPixels; }
    [[nodiscard]] std::vector<uint8_t> takePixels() noexcept { return std::move(mPixels); }

private:
    HostImageCopy mCopy;
    std::vector<uint8_t> mPixels;
};

// Views composed into one image of a given size, each blitted into its place (the two eyes of a
// side-by-side HMD frame), then copied to host memory like ReadbackTarget.
class CompositeReadbackTarget final : public OutputTarget {
public:
    CompositeReadbackTarget(vk::Context& ctx, uint32_t width, uint32_t height)
        : mCtx(ctx), mWidth(width), mHeight(height) {}
    void place(const std::string& view, VkRect2D rect) { mPlaces[view] = rect; }
    void beginFrame(rg::RenderGraph& graph) override;
    void addOutput(rg::RenderGraph& graph, rg::TextureId image, const View& view) override;
    void endFrame(rg::RenderGraph& graph) override;
    [[nodiscard]] bool waitsForFrame() const noexcept override { return true; }
    void frameFinished() override;
    [[nodiscard]] const std::vector<uint8_t>& pixels() const noexcept { return mPixels; }
    [[nodiscard]] uint32_t width() const noexcept { return mWidth; }
    [[nodiscard]] uint32_t height() const noexcept { return mHeight; }

private:
    vk::Context& mCtx;
    uint32_t mWidth, mHeight;
    std::map<std::string, VkRect2D> mPlaces;
    rg::TextureId mImage;
    std::optional<vk::Buffer> mHost;
    std::vector<uint8_t> mPixels;
};

// Keeps the image on the GPU (benchmarks, a frame nobody looks at): a sink and nothing else.
class DiscardTarget final : public OutputTarget {
public:
    void addOutput(rg::RenderGraph& graph, rg::TextureId image, const View& view) override;
};

} // namespace gt::render
