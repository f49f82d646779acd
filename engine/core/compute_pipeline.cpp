#include "engine/core/compute_pipeline.h"

#include <map>
#include <stdexcept>

namespace engine {

ComputePipeline::ComputePipeline(const GpuContext& context, std::span<const uint32_t> spirv,
                                 const std::vector<vk::DescriptorType>& bindings, uint32_t pushConstantBytes,
                                 const std::string& debugName, std::span<const int32_t> specialization,
                                 uint32_t descriptorSetCount)
    : mContext(&context),
      mBindingTypes(bindings),
      mPushConstantBytes(pushConstantBytes),
      mShader(context.device(), vk::ShaderModuleCreateInfo({}, spirv.size_bytes(), spirv.data())) {
    std::vector<vk::DescriptorSetLayoutBinding> layoutBindings;
    std::map<vk::DescriptorType, uint32_t> typeCounts;
    for (uint32_t i = 0; i < bindings.size(); ++i) {
        layoutBindings.emplace_back(i, bindings[i], 1, vk::ShaderStageFlagBits::eCompute);
        ++typeCounts[bindings[i]];
    }
    mSetLayout = vk::raii::DescriptorSetLayout(context.device(), vk::DescriptorSetLayoutCreateInfo({}, layoutBindings));

    vk::PushConstantRange pushRange(vk::ShaderStageFlagBits::eCompute, 0, pushConstantBytes);
    vk::PipelineLayoutCreateInfo layoutInfo({}, *mSetLayout);
    if (pushConstantBytes > 0) layoutInfo.setPushConstantRanges(pushRange);
    mPipelineLayout = vk::raii::PipelineLayout(context.device(), layoutInfo);

    std::vector<vk::SpecializationMapEntry> entries;
    for (uint32_t i = 0; i < specialization.size(); ++i) entries.emplace_back(i, i * 4u, 4u);
    const vk::SpecializationInfo specializationInfo(static_cast<uint32_t>(entries.size()), entries.data(),
                                                    specialization.size_bytes(), specialization.data());
    vk::PipelineShaderStageCreateInfo stage({}, vk::ShaderStageFlagBits::eCompute, *mShader, "main",
                                            specialization.empty() ? nullptr : &specializationInfo);
    mPipeline = vk::raii::Pipeline(context.device(), nullptr, vk::ComputePipelineCreateInfo({}, stage, *mPipelineLayout));
    context.setDebugName(mPipeline, debugName);

    std::vector<vk::DescriptorPoolSize> poolSizes;
    if (descriptorSetCount < 1 || descriptorSetCount > 1024) {
        throw std::invalid_argument(debugName + ": descriptor set count must be 1..1024");
    }
    for (const auto& [type, count] : typeCounts) poolSizes.emplace_back(type, count * descriptorSetCount);
    mDescriptorPool = vk::raii::DescriptorPool(
        context.device(), vk::DescriptorPoolCreateInfo(vk::DescriptorPoolCreateFlagBits::eFreeDescriptorSet,
                                                       descriptorSetCount, poolSizes));
    const std::vector<vk::DescriptorSetLayout> layouts(descriptorSetCount, *mSetLayout);
    vk::raii::DescriptorSets sets(context.device(), vk::DescriptorSetAllocateInfo(*mDescriptorPool, layouts));
    for (auto& set : sets) mDescriptorSets.push_back(std::move(set));
}

const vk::raii::DescriptorSet& ComputePipeline::descriptorSet(uint32_t set) const {
    if (set >= mDescriptorSets.size()) {
        throw std::logic_error("descriptor set " + std::to_string(set) + " of a pipeline that has " +
                               std::to_string(mDescriptorSets.size()));
    }
    return mDescriptorSets[set];
}

void ComputePipeline::bindBuffer(uint32_t binding, const GpuBuffer& buffer, uint32_t set) {
    vk::DescriptorBufferInfo info(*buffer.buffer(), 0, VK_WHOLE_SIZE);
    mContext->device().updateDescriptorSets(
        vk::WriteDescriptorSet(*descriptorSet(set), binding, 0, mBindingTypes.at(binding), {}, info), {});
}

void ComputePipeline::bindStorageImage(uint32_t binding, const GpuImage& image, uint32_t set) {
    vk::DescriptorImageInfo info({}, *image.view(), vk::ImageLayout::eGeneral);
    mContext->device().updateDescriptorSets(
        vk::WriteDescriptorSet(*descriptorSet(set), binding, 0, mBindingTypes.at(binding), info), {});
}

void ComputePipeline::bindSampledImage(uint32_t binding, const GpuImage& image, const vk::raii::Sampler& sampler,
                                       uint32_t set) {
    vk::DescriptorImageInfo info(*sampler, *image.view(), vk::ImageLayout::eShaderReadOnlyOptimal);
    mContext->device().updateDescriptorSets(
        vk::WriteDescriptorSet(*descriptorSet(set), binding, 0, mBindingTypes.at(binding), info), {});
}

void ComputePipeline::recordDispatch(const vk::raii::CommandBuffer& commands, vk::Extent3D groups,
                                     std::span<const std::byte> pushConstants, uint32_t set) const {
    if (pushConstants.size() != mPushConstantBytes) {
        throw std::logic_error("push constants of " + std::to_string(pushConstants.size()) +
                               " bytes for a pipeline that declares " + std::to_string(mPushConstantBytes));
    }
    commands.bindPipeline(vk::PipelineBindPoint::eCompute, *mPipeline);
    commands.bindDescriptorSets(vk::PipelineBindPoint::eCompute, *mPipelineLayout, 0, *descriptorSet(set), {});
    if (!pushConstants.empty()) {
        commands.pushConstants<std::byte>(*mPipelineLayout, vk::ShaderStageFlagBits::eCompute, 0, pushConstants);
    }
    commands.dispatch(groups.width, groups.height, groups.depth);
}

}  // namespace engine
