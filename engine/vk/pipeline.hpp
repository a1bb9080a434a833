#pragma once
// A compute pipeline with one push-descriptor set (VK_KHR_push_descriptor) and one push-constant
// range: passes bind by the binding constants in shaders/shared/*_shared.h and never manage
// descriptor pools.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace gt::vk {

class Context;

struct ComputePipelineDesc {
    std::string name;
    std::span<const uint32_t> spirv;
    std::vector<VkDescriptorType> bindings; // binding i has type bindings[i]
    uint32_t pushConstantSize = 0;
    std::vector<uint32_t> specialization; // constant_id i takes specialization[i]
};

class ComputePipeline {
public:
    ComputePipeline(Context& ctx, const ComputePipelineDesc& desc);
    ~ComputePipeline();
    ComputePipeline(const ComputePipeline&) = delete;
    ComputePipeline& operator=(const ComputePipeline&) = delete;

    [[nodiscard]] VkPipeline handle() const noexcept { return mPipeline; }
    [[nodiscard]] VkPipelineLayout layout() const noexcept { return mLayout; }
    [[nodiscard]] const std::string& name() const noexcept { return mName; }

private:
    VkDevice mDevice;
    std::string mName;
    VkDescriptorSetLayout mSetLayout = VK_NULL_HANDLE;
    VkPipelineLayout mLayout = VK_NULL_HANDLE;
    VkPipeline mPipeline = VK_NULL_HANDLE;
};

// Collects descriptor writes for one push-descriptor update. Holds the info structs so their
// addresses stay valid until push().
class DescriptorWriter {
public:
    DescriptorWriter& storageImage(uint32_t binding, VkImageView view);
    DescriptorWriter& sampledImage(uint32_t binding, VkImageView view, VkSampler sampler);
    DescriptorWriter& storageBuffer(uint32_t binding, VkBuffer buffer,
                                    VkDeviceSize size = VK_WHOLE_SIZE);
    DescriptorWriter& uniformBuffer(uint32_t binding, VkBuffer buffer,
                                    VkDeviceSize size = VK_WHOLE_SIZE);
    DescriptorWriter& texelBuffer(uint32_t binding, VkBufferView view);
    void push(const Context& ctx, VkCommandBuffer cmd, const ComputePipeline& pipeline);

private:
    struct Entry {
        uint32_t binding;
        VkDescriptorType type;
        VkDescriptorImageInfo image;
        VkDescriptorBufferInfo buffer;
        VkBufferView texel;
    };
    std::vector<Entry> mEntries;
};

// Binds, pushes constants and dispatches in one call.
void dispatch(VkCommandBuffer cmd, const ComputePipeline& pipeline, const void* pushConstants,
              uint32_t pushSize, uint32_t groupsX, uint32_t groupsY, uint32_t groupsZ = 1);

} // namespace gt::vk
