#include "vk/pipeline.hpp"

#include "core/error.hpp"
#include "vk/context.hpp"

namespace gt::vk {

ComputePipeline::ComputePipeline(Context& ctx, const ComputePipelineDesc& desc)
    : mDevice(ctx.device()), mName(desc.name) {
    std::vector<VkDescriptorSetLayoutBinding> bindings;
    for (uint32_t i = 0; i < desc.bindings.size(); ++i) {
        bindings.push_back({i, desc.bindings[i], 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
    }
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
    setInfo.bindingCount = static_cast<uint32_t>(bindings.size());
    setInfo.pBindings = bindings.data();
    GT_VK_CHECK(vkCreateDescriptorSetLayout(mDevice, &setInfo, nullptr, &mSetLayout));

    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, desc.pushConstantSize};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.setLayoutCount = 1;
    layoutInfo.pSetLayouts = &mSetLayout;
    layoutInfo.pushConstantRangeCount = desc.pushConstantSize > 0 ? 1 : 0;
    layoutInfo.pPushConstantRanges = &range;
    VkShaderModule module = VK_NULL_HANDLE;
    try {
        GT_VK_CHECK(vkCreatePipelineLayout(mDevice, &layoutInfo, nullptr, &mLayout));
        VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        moduleInfo.codeSize = desc.spirv.size_bytes();
        moduleInfo.pCode = desc.spirv.data();
        GT_VK_CHECK(vkCreateShaderModule(mDevice, &moduleInfo, nullptr, &module));
        VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        info.stage.module = module;
        info.stage.pName = "main";
        std::vector<VkSpecializationMapEntry> entries;
        for (uint32_t i = 0; i < desc.specialization.size(); ++i) {
            entries.push_back({i, i * 4u, 4u});
        }
        VkSpecializationInfo spec{static_cast<uint32_t>(entries.size()), entries.data(),
                                  desc.specialization.size() * 4u, desc.specialization.data()};
        if (!entries.empty()) info.stage.pSpecializationInfo = &spec;
        info.layout = mLayout;
        GT_VK_CHECK(
            vkCreateComputePipelines(mDevice, VK_NULL_HANDLE, 1, &info, nullptr, &mPipeline));
        vkDestroyShaderModule(mDevice, module, nullptr);
    } catch (...) {
        if (module != VK_NULL_HANDLE) vkDestroyShaderModule(mDevice, module, nullptr);
        if (mLayout != VK_NULL_HANDLE) vkDestroyPipelineLayout(mDevice, mLayout, nullptr);
        vkDestroyDescriptorSetLayout(mDevice, mSetLayout, nullptr);
        throw;
    }
    ctx.setName(VK_OBJECT_TYPE_PIPELINE, reinterpret_cast<uint64_t>(mPipeline), mName);
}

ComputePipeline::~ComputePipeline() {
    vkDestroyPipeline(mDevice, mPipeline, nullptr);
    vkDestroyPipelineLayout(mDevice, mLayout, nullptr);
    vkDestroyDescriptorSetLayout(mDevice, mSetLayout, nullptr);
}

DescriptorWriter& DescriptorWriter::storageImage(uint32_t binding, VkImageView view) {
    mEntries.push_back({binding,
                        VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                        {VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL},
                        {},
                        VK_NULL_HANDLE});
    return *this;
}

DescriptorWriter& DescriptorWriter::sampledImage(uint32_t binding, VkImageView view,
                                                 VkSampler sampler) {
    mEntries.push_back({binding,
                        VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                        {sampler, view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
                        {},
                        VK_NULL_HANDLE});
    return *this;
}

DescriptorWriter& DescriptorWriter::storageBuffer(uint32_t binding, VkBuffer buffer,
                                                  VkDeviceSize size) {
    mEntries.push_back(
        {binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, {}, {buffer, 0, size}, VK_NULL_HANDLE});
    return *this;
}

DescriptorWriter& DescriptorWriter::uniformBuffer(uint32_t binding, VkBuffer buffer,
                                                  VkDeviceSize size) {
    mEntries.push_back(
        {binding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, {}, {buffer, 0, size}, VK_NULL_HANDLE});
    return *this;
}

DescriptorWriter& DescriptorWriter::texelBuffer(uint32_t binding, VkBufferView view) {
    mEntries.push_back({binding, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, {}, {}, view});
    return *this;
}

void DescriptorWriter::push(const Context& ctx, VkCommandBuffer cmd,
                            const ComputePipeline& pipeline) {
    std::vector<VkWriteDescriptorSet> writes;
    writes.reserve(mEntries.size());
    for (const Entry& e : mEntries) {
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstBinding = e.binding;
        w.descriptorCount = 1;
        w.descriptorType = e.type;
        switch (e.type) {
        case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE:
        case VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER:
            w.pImageInfo = &e.image;
            break;
        case VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER:
            w.pTexelBufferView = &e.texel;
            break;
        default:
            w.pBufferInfo = &e.buffer;
            break;
        }
        writes.push_back(w);
    }
    ctx.pushDescriptorSet(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.layout(), 0,
                          static_cast<uint32_t>(writes.size()), writes.data());
}

void dispatch(VkCommandBuffer cmd, const ComputePipeline& pipeline, const void* pushConstants,
              uint32_t pushSize, uint32_t groupsX, uint32_t groupsY, uint32_t groupsZ) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
    if (pushSize > 0) {
        vkCmdPushConstants(cmd, pipeline.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, pushSize,
                           pushConstants);
    }
    vkCmdDispatch(cmd, groupsX, groupsY, groupsZ);
}

} // namespace gt::vk
