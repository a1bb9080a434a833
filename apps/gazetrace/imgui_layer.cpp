#include "imgui_layer.hpp"

#include <algorithm>
#include <array>
#include <string>

#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include "core/error.hpp"
#include "core/log.hpp"
#include "vk/context.hpp"
#include "window.hpp"

namespace gt::app {

namespace {
void checkVk(VkResult r) {
    if (r != VK_SUCCESS) {
        log::error("overlay: Vulkan call failed with " + std::to_string(r));
    }
}
} // namespace

ImGuiLayer::ImGuiLayer(Window& window, vk::Context& ctx, VkFormat format, uint32_t imageCount)
    : mCtx(ctx), mPass(ctx, format) {
    const std::array<VkDescriptorPoolSize, 1> sizes = {
        VkDescriptorPoolSize{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 16}};
    VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pi.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    pi.maxSets = 16;
    pi.poolSizeCount = static_cast<uint32_t>(sizes.size());
    pi.pPoolSizes = sizes.data();
    GT_VK_CHECK(vkCreateDescriptorPool(ctx.device(), &pi, nullptr, &mPool));
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr; // no imgui.ini left in the working folder
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForVulkan(window.handle(), true);
    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = ctx.instance();
    info.PhysicalDevice = ctx.physicalDevice();
    info.Device = ctx.device();
    info.QueueFamily = ctx.queueFamily();
    info.Queue = ctx.queue();
    info.DescriptorPool = mPool;
    info.MinImageCount = std::max(2u, imageCount);
    info.ImageCount = std::max(2u, imageCount);
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    info.CheckVkResultFn = checkVk;
    ImGui_ImplVulkan_Init(&info, mPass.renderPass());
    ctx.submitAndWait([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
    ImGui_ImplVulkan_DestroyFontUploadObjects();
}

ImGuiLayer::~ImGuiLayer() {
    vkDeviceWaitIdle(mCtx.device());
    ImGui_ImplVulkan_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    vkDestroyDescriptorPool(mCtx.device(), mPool, nullptr);
}

void ImGuiLayer::newFrame() {
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
}

void ImGuiLayer::swapchainRecreated(uint32_t imageCount) {
    mPass.releaseFramebuffers();
    ImGui_ImplVulkan_SetMinImageCount(std::max(2u, imageCount));
}

rg::TextureId ImGuiLayer::add(rg::RenderGraph& graph, rg::TextureId image) {
    return mPass.add(graph, image, [](VkCommandBuffer cmd) {
        if (ImDrawData* d = ImGui::GetDrawData(); d != nullptr && d->CmdListsCount > 0) {
            ImGui_ImplVulkan_RenderDrawData(d, cmd);
        }
    });
}

} // namespace gt::app
