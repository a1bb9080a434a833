#pragma once
// Full resolution: every pixel ray traced with N stratified, jittered rays — the reference every
// foveated method is measured against.
#include "foveation_method.hpp"
#include "reference/reference.hpp"

namespace gt::render {

class FullResolution final : public FoveationMethod {
public:
    explicit FullResolution(const MethodContext& mc, passes::ReferenceSettings settings = {});
    [[nodiscard]] std::string_view name() const override { return "reference"; }
    [[nodiscard]] MethodImage addRadiance(rg::RenderGraph& graph, const View& view) override;
    [[nodiscard]] uint64_t rays(const View& view) const override;
    [[nodiscard]] std::optional<WarmUp> warmUp(const View& view) override;

    // Rays per pixel and the frame's seed (a sequence changes it every frame).
    passes::ReferenceSettings settings;

private:
    MethodContext mMc;
    passes::ReferencePass mPass;
    bool mWarm = false;
};

} // namespace gt::render
