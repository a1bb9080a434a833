#include "xr_eye_fill.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gt::app {

namespace {

// One bar of the cross, clipped to the image; empty when it lies outside.
std::optional<VkBufferImageCopy> bar(glm::ivec2 lo, glm::ivec2 hi, VkExtent2D extent,
                                     uint32_t layer) {
    lo = glm::max(lo, glm::ivec2(0));
    hi = glm::min(hi, glm::ivec2(static_cast<int>(extent.width), static_cast<int>(extent.height)));
    if (hi.x <= lo.x || hi.y <= lo.y) {
        return std::nullopt;
    }
    VkBufferImageCopy c{};
    c.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, layer, 1};
    c.imageOffset = {lo.x, lo.y, 0};
    c.imageExtent = {static_cast<uint32_t>(hi.x - lo.x), static_cast<uint32_t>(hi.y - lo.y), 1};
    return c;
}

VkImageMemoryBarrier layoutBarrier(VkImage image, uint32_t layer, VkImageLayout from,
                                   VkImageLayout to, VkAccessFlags srcAccess,
                                   VkAccessFlags dstAccess) {
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.srcAccessMask = srcAccess;
    b.dstAccessMask = dstAccess;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, layer, 1};
    return b;
}

} // namespace

void EyeFill::fill(const render::ExternalImage& image, const std::optional<FixationCross>& cross) {
    std::vector<VkBufferImageCopy> bars;
    if (cross) {
        const glm::ivec2 c(static_cast<int>(std::lround(cross->centrePx.x)),
                           static_cast<int>(std::lround(cross->centrePx.y)));
        const int arm = static_cast<int>(cross->armPx);
        const int half = static_cast<int>(cross->thickPx / 2);
        const int thick = static_cast<int>(std::max(cross->thickPx, 1u));
        for (const auto& b : {bar({c.x - arm, c.y - half}, {c.x + arm + 1, c.y - half + thick},
                                  image.extent, image.layer),
                              bar({c.x - half, c.y - arm}, {c.x - half + thick, c.y + arm + 1},
                                  image.extent, image.layer)}) {
            if (b) {
                bars.push_back(*b);
            }
        }
        // Every swapchain format gazetrace takes is 8-bit RGBA or BGRA: white is all ones.
        const VkDeviceSize bytes =
            VkDeviceSize(2 * cross->armPx + 1) * VkDeviceSize(std::max(cross->thickPx, 1u)) * 4;
        if (!mWhite.valid() || mWhite.size() < bytes) {
            mWhite = vk::Buffer(mCtx, {bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                       vk::MemoryUsage::Upload, "xr.fixation_cross"});
            const std::vector<std::byte> white(bytes, std::byte{0xff});
            mWhite.upload(white);
        }
    }
    mCtx.submitAndWait([&](VkCommandBuffer cmd) {
        // Everything is overwritten: the earlier contents need not be kept.
        const VkImageMemoryBarrier toTransfer =
            layoutBarrier(image.image, image.layer, VK_IMAGE_LAYOUT_UNDEFINED,
                          VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_ACCESS_TRANSFER_WRITE_BIT);
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             0, 0, nullptr, 0, nullptr, 1, &toTransfer);
        const VkClearColorValue black{{0.0f, 0.0f, 0.0f, 1.0f}};
        const VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, image.layer, 1};
        vkCmdClearColorImage(cmd, image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &black, 1,
                             &all);
        if (!bars.empty()) {
            // The clear and the copies write the same texels: the copies go second.
            VkMemoryBarrier cleared{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
            cleared.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            cleared.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                                 VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &cleared, 0, nullptr, 0,
                                 nullptr);
            vkCmdCopyBufferToImage(cmd, mWhite.handle(), image.image,
                                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                   static_cast<uint32_t>(bars.size()), bars.data());
        }
        const VkImageMemoryBarrier toAttachment = layoutBarrier(
            image.image, image.layer, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_ACCESS_TRANSFER_WRITE_BIT,
            VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0, 0, nullptr, 0,
                             nullptr, 1, &toAttachment);
    });
}

} // namespace gt::app
