#pragma once
// The frames of an OpenXR session that show no scene (a study's fixation, blank, response and
// break frames): each eye's swapchain image cleared to black, with a white cross at the
// fixation point where one is asked for. Written with transfer commands only (a clear and two
// buffer-to-image copies), so no pipeline is needed; the image is left in
// COLOR_ATTACHMENT_OPTIMAL, as OpenXR requires of a released Vulkan swapchain image.
#include <cstdint>
#include <optional>

#include <glm/glm.hpp>

#include "external_image_target.hpp"
#include "vk/context.hpp"
#include "vk/resources.hpp"

namespace gt::app {

struct FixationCross {
    glm::vec2 centrePx{}; // in the eye image's pixels
    uint32_t armPx = 8;   // from the centre to each end
    uint32_t thickPx = 2;
};

class EyeFill {
public:
    explicit EyeFill(vk::Context& ctx) : mCtx(ctx) {}
    // Writes `image` (acquired and waited for) and waits until it is written.
    void fill(const render::ExternalImage& image, const std::optional<FixationCross>& cross);

private:
    vk::Context& mCtx;
    vk::Buffer mWhite; // opaque white texels for the cross, grown as needed
};

} // namespace gt::app
