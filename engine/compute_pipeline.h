/// @brief A compute pipeline built from embedded SPIR-V, with its descriptor set layout,
/// pipeline layout and one descriptor set, and the calls to fill and dispatch it.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "engine/gpu_buffer.h"
#include "engine/gpu_context.h"
#include "engine/gpu_image.h"

namespace engine {

class ComputePipeline {
public:
    /// `bindings` lists the descriptor type of binding 0, 1, 2, ... in order;
    /// `specialization[i]` is the value of the shader's 32-bit constant_id i.
    ComputePipeline(const GpuContext& context, std::span<const uint32_t> spirv,
                    const std::vector<vk::DescriptorType>& bindings, uint32_t pushConstantBytes,
                    const std::string& debugName, std::span<const int32_t> specialization = {});

    void bindBuffer(uint32_t binding, const GpuBuffer& buffer);
    void bindStorageImage(uint32_t binding, const GpuImage& image);
    void bindSampledImage(uint32_t binding, const GpuImage& image, const vk::raii::Sampler& sampler);

    /// Records the bind and a dispatch of `groups` work groups; `pushConstants` may be empty.
    void recordDispatch(const vk::raii::CommandBuffer& commands, vk::Extent3D groups,
                        std::span<const std::byte> pushConstants = {}) const;

private:
    const GpuContext* mContext;
    std::vector<vk::DescriptorType> mBindingTypes;
    uint32_t mPushConstantBytes;
    vk::raii::ShaderModule mShader;
    vk::raii::DescriptorSetLayout mSetLayout{nullptr};
    vk::raii::PipelineLayout mPipelineLayout{nullptr};
    vk::raii::Pipeline mPipeline{nullptr};
    vk::raii::DescriptorPool mDescriptorPool{nullptr};
    vk::raii::DescriptorSet mDescriptorSet{nullptr};
};

}  // namespace engine
