/// @brief A compute pipeline built from embedded SPIR-V, with its descriptor set layout,
/// pipeline layout and descriptor sets, and the calls to fill and dispatch it.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "engine/core/gpu_buffer.h"
#include "engine/core/gpu_context.h"
#include "engine/core/gpu_image.h"

namespace engine {

class ComputePipeline {
public:
    /// `bindings` lists the descriptor type of binding 0, 1, 2, ... in order;
    /// `specialization[i]` is the value of the shader's 32-bit constant_id i. The pipeline has
    /// `descriptorSetCount` sets of the same layout, so that several dispatches with other
    /// resources can be recorded into one command buffer (set i for the i-th of them).
    ComputePipeline(const GpuContext& context, std::span<const uint32_t> spirv,
                    const std::vector<vk::DescriptorType>& bindings, uint32_t pushConstantBytes,
                    const std::string& debugName, std::span<const int32_t> specialization = {},
                    uint32_t descriptorSetCount = 1);

    void bindBuffer(uint32_t binding, const GpuBuffer& buffer, uint32_t set = 0);
    void bindStorageImage(uint32_t binding, const GpuImage& image, uint32_t set = 0);
    void bindSampledImage(uint32_t binding, const GpuImage& image, const vk::raii::Sampler& sampler, uint32_t set = 0);

    /// Records the bind of descriptor set `set` and a dispatch of `groups` work groups;
    /// `pushConstants` may be empty.
    void recordDispatch(const vk::raii::CommandBuffer& commands, vk::Extent3D groups,
                        std::span<const std::byte> pushConstants = {}, uint32_t set = 0) const;

private:
    const GpuContext* mContext;
    std::vector<vk::DescriptorType> mBindingTypes;
    uint32_t mPushConstantBytes;
    vk::raii::ShaderModule mShader;
    vk::raii::DescriptorSetLayout mSetLayout{nullptr};
    vk::raii::PipelineLayout mPipelineLayout{nullptr};
    vk::raii::Pipeline mPipeline{nullptr};
    vk::raii::DescriptorPool mDescriptorPool{nullptr};
    std::vector<vk::raii::DescriptorSet> mDescriptorSets;

    [[nodiscard]] const vk::raii::DescriptorSet& descriptorSet(uint32_t set) const;
};

}  // namespace engine
