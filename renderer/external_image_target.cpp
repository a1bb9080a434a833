#include "external_image_target.hpp"

#include "blit/blit.hpp"
#include "copy/copy.hpp"
#include "core/error.hpp"
#include "view.hpp"

namespace gt::render {

void ExternalImageTarget::addOutput(rg::RenderGraph& graph, rg::TextureId image,
                                    const View& view) {
    if (!mImage) throw Error("external image target: no image handed over for this frame");
    if (mScreenshotWanted) mScreenshotCopy.add(graph, "screenshot", image, view.width, view.height);
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
    const rg::TextureId srgb =
        passes::addCopyPass(graph, "xr.srgb", image, VK_FORMAT_R8G8B8A8_SRGB, view.width,
                            view.height);
    const rg::TextureId written = passes::addBlitPass(
        graph, "xr.blit", srgb, target, {{0, 0}, mImage->extent});
    graph.sink(written, rg::Access::ColorAttachment);
    mImage.reset(); // one frame only: the caller releases it after the submit
}

void ExternalImageTarget::frameFinished() {
    if (!mScreenshotWanted || !mScreenshotCopy.recorded()) return;
    mScreenshot = mScreenshotCopy.download();
    mScreenshotWanted = false;
}

} // namespace gt::render
