#include "external_image_target.hpp"

#include <array>
#include <cmath>
#include <utility>

#include "blit/blit.hpp"
#include "core/error.hpp"
#include "view.hpp"

namespace gt::render {

void ExternalImageTarget::addOutput(rg::RenderGraph& graph, rg::TextureId image, const View& view) {
    if (!mImage) {
        throw Error("external image target: no image handed over for this frame");
    }
    rg::ImportedTexture t;
    t.image = mImage->image;
    t.format = mImage->format;
    t.width = mImage->extent.width;
    t.height = mImage->extent.height;
    t.layer = mImage->layer;
    // Contents undefined: the blit overwrites all of it. The first barrier waits for all
    // earlier work on the queue, where the runtime recorded its own hand-over of the image.
    t.acquireStage = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    const rg::TextureId target = graph.importTexture("xr.image", t);
    const rg::TextureId srgb = passes::addCopyPass(graph, "xr.srgb", image, VK_FORMAT_R8G8B8A8_SRGB,
                                                   view.width, view.height);
    const rg::TextureId written =
        passes::addBlitPass(graph, "xr.blit", srgb, target, {{0, 0}, mImage->extent});
    if (mScreenshotWanted) {
        // What the runtime receives, read back from its own image.
        mScreenshotCopy.add(graph, "screenshot", written, mImage->extent.width,
                            mImage->extent.height);
        mScreenshotFormat = mImage->format;
    }
    graph.sink(written, rg::Access::ColorAttachment);
    mImage.reset(); // one frame only: the caller releases it after the submit
}

void ExternalImageTarget::frameFinished() {
    if (!mScreenshotWanted || !mScreenshotCopy.recorded()) {
        return;
    }
    std::vector<uint8_t> px = mScreenshotCopy.download();
    const bool bgra = mScreenshotFormat == VK_FORMAT_B8G8R8A8_SRGB ||
                      mScreenshotFormat == VK_FORMAT_B8G8R8A8_UNORM;
    const bool linear = mScreenshotFormat == VK_FORMAT_R8G8B8A8_UNORM ||
                        mScreenshotFormat == VK_FORMAT_B8G8R8A8_UNORM;
    // sRGB encoding of a linear byte (IEC 61966-2-1), for images that hold linear values.
    std::array<uint8_t, 256> encode{};
    for (int i = 0; i < 256; ++i) {
        const double c = i / 255.0;
        const double e = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
        encode[static_cast<std::size_t>(i)] = static_cast<uint8_t>(std::lround(e * 255.0));
    }
    for (std::size_t i = 0; i + 3 < px.size(); i += 4) {
        if (bgra) {
            std::swap(px[i], px[i + 2]);
        }
        if (linear) {
            for (std::size_t c = 0; c < 3; ++c) {
                px[i + c] = encode[px[i + c]];
            }
        }
    }
    mScreenshot = std::move(px);
    mScreenshotWanted = false;
}

} // namespace gt::render
