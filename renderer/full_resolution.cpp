#include "full_resolution.hpp"

#include "view.hpp"

namespace gt::render {

FullResolution::FullResolution(const MethodContext& mc, passes::ReferenceSettings s)
    : settings(s), mMc(mc), mPass(mc.ctx) {}

MethodImage FullResolution::addRadiance(rg::RenderGraph& graph, const View& view) {
    const passes::ReferenceImage image =
        mPass.addImage(graph, mMc.scene, view.cameraPush(), settings);
    return {image.radiance, std::nullopt, image.motion};
}

uint64_t FullResolution::rays(const View& view) const {
    return static_cast<uint64_t>(view.width) * view.height * settings.raysPerPixel;
}

std::optional<WarmUp> FullResolution::warmUp(const View& view) {
    if (mWarm) {
        return std::nullopt;
    }
    mWarm = true;
    // One pipeline whatever the size or ray count: a 16 x 16 frame at one ray compiles it.
    const shaders::trace::CameraPush cam = view.cameraPush();
    return WarmUp{16, 16, [this, cam](rg::RenderGraph& g) {
                      return mPass.add(g, mMc.scene, cam, {1, 0});
                  }};
}

} // namespace gt::render
