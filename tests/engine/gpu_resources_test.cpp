// Device creation, bit-exact buffer and 3D-image round trips, and a compute dispatch with a
// known result, all under the validation layer.
#include <numeric>
#include <random>

#include <gtest/gtest.h>

#include "affine_fill_spv.h"
#include "engine/core/command_submission.h"
#include "engine/core/compute_pipeline.h"
#include "engine/core/gpu_buffer.h"
#include "engine/render/volume_texture.h"
#include "tests/support/gpu_test_fixture.h"

namespace {

using testing_support::GpuTest;

class GpuResources : public GpuTest {};

TEST_F(GpuResources, CreatesDeviceWithComputeQueue) {
    EXPECT_FALSE(context().deviceName().empty());
    EXPECT_TRUE(context().isValidationEnabled());
    EXPECT_NE(*context().device(), vk::Device{});
}

TEST_F(GpuResources, BufferRoundTripThroughDeviceMemoryIsBitExact) {
    constexpr std::size_t kCount = 1 << 16;
    std::vector<uint32_t> values(kCount);
    std::mt19937 random(7);
    for (auto& v : values) v = static_cast<uint32_t>(random());
    const vk::DeviceSize bytes = kCount * sizeof(uint32_t);

    engine::GpuBuffer upload(context(), bytes, vk::BufferUsageFlagBits::eTransferSrc, engine::GpuBuffer::Memory::HostVisible,
                             "test upload");
    engine::GpuBuffer onDevice(context(), bytes,
                               vk::BufferUsageFlagBits::eTransferSrc | vk::BufferUsageFlagBits::eTransferDst,
                               engine::GpuBuffer::Memory::DeviceLocal, "test device buffer");
    engine::GpuBuffer download(context(), bytes, vk::BufferUsageFlagBits::eTransferDst,
                               engine::GpuBuffer::Memory::HostVisible, "test download");
    upload.write(std::as_bytes(std::span(values)));
    engine::submitAndWait(context(), [&](const vk::raii::CommandBuffer& commands) {
        commands.copyBuffer(*upload.buffer(), *onDevice.buffer(), vk::BufferCopy(0, 0, bytes));
        vk::MemoryBarrier barrier(vk::AccessFlagBits::eTransferWrite, vk::AccessFlagBits::eTransferRead);
        commands.pipelineBarrier(vk::PipelineStageFlagBits::eTransfer, vk::PipelineStageFlagBits::eTransfer, {},
                                 barrier, {}, {});
        commands.copyBuffer(*onDevice.buffer(), *download.buffer(), vk::BufferCopy(0, 0, bytes));
    });
    std::vector<uint32_t> back(kCount);
    download.read(std::as_writable_bytes(std::span(back)));
    EXPECT_EQ(back, values);
}

TEST_F(GpuResources, VolumeImageRoundTripKeepsEveryInt16) {
    // Odd sizes, every extreme of int16 and a slab split (the upload goes in 32 MiB slabs).
    volumes::Volume volume;
    volume.dims = {67, 45, 31};
    volume.hu.resize(volume.voxelCount());
    std::mt19937 random(11);
    std::uniform_int_distribution<int> any(-32768, 32767);
    for (auto& v : volume.hu) v = static_cast<int16_t>(any(random));
    volume.hu[0] = -32768;
    volume.hu[1] = 32767;
    volume.hu[2] = 0;
    volume.hu[3] = -1;
    engine::VolumeTexture texture(context(), volume);
    EXPECT_EQ(texture.readBackHu(), volume.hu);
}

TEST_F(GpuResources, LargeVolumeUploadsInSlabs) {
    volumes::Volume volume;
    volume.dims = {512, 256, 160};  // 40 MiB: two slabs
    volume.hu.resize(volume.voxelCount());
    for (std::size_t i = 0; i < volume.hu.size(); ++i) volume.hu[i] = static_cast<int16_t>((i * 2654435761u) >> 16);
    engine::VolumeTexture texture(context(), volume);
    EXPECT_EQ(texture.readBackHu(), volume.hu);
}

TEST_F(GpuResources, MemoryBeyondOneAllocationIsRefusedBeforeAllocating) {
    const vk::DeviceSize largest = context().largestAllocationBytes(vk::MemoryPropertyFlagBits::eDeviceLocal);
    ASSERT_GT(largest, vk::DeviceSize{0});
    try {
        // Creating the buffer costs nothing; its memory would be one byte too many.
        const engine::GpuBuffer buffer(context(), largest + 1, vk::BufferUsageFlagBits::eStorageBuffer,
                                       engine::GpuBuffer::Memory::DeviceLocal, "oversized test buffer");
        ADD_FAILURE() << "a buffer of " << largest + 1 << " bytes was allocated";
    } catch (const engine::DeviceMemoryError& e) {
        EXPECT_NE(std::string(e.what()).find("oversized test buffer needs"), std::string::npos) << e.what();
        EXPECT_EQ(e.largestBytes(), largest);
    }
}

TEST_F(GpuResources, VolumeTooLargeForTheDeviceSaysHowManySlicesFit) {
    EXPECT_EQ(engine::VolumeTexture::slicesThatFit({1100, 1100, 1000}, vk::DeviceSize{1} << 31), 887);  // 2^31 / 2420000
    EXPECT_EQ(engine::VolumeTexture::slicesThatFit({4, 4, 10}, 1u << 20), 10);  // all of them
    EXPECT_EQ(engine::VolumeTexture::bytesFor({512, 512, 451}), vk::DeviceSize{236453888});

    // A volume one slice past what one image may hold; its voxels are never touched, since the
    // size is refused before anything is allocated or uploaded.
    const uint32_t side = std::min<uint32_t>(context().physicalDevice().getProperties().limits.maxImageDimension3D, 4096);
    const vk::DeviceSize largest = context().largestAllocationBytes(vk::MemoryPropertyFlagBits::eDeviceLocal);
    const vk::DeviceSize slices = largest / (vk::DeviceSize{side} * side * 2) + 1;
    if (slices > side) GTEST_SKIP() << "this device holds any volume its image limit allows";
    volumes::Volume volume;
    volume.dims = {static_cast<int>(side), static_cast<int>(side), static_cast<int>(slices)};
    try {
        const engine::VolumeTexture texture(context(), volume);
        ADD_FAILURE() << "an oversized volume was accepted";
    } catch (const engine::DeviceMemoryError& e) {
        const std::string fits = "at most " + std::to_string(slices - 1) + " of its slices fit";
        EXPECT_NE(std::string(e.what()).find(fits), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(context().deviceName()), std::string::npos) << e.what();
    }
}

TEST_F(GpuResources, ComputeDispatchProducesKnownResult) {
    constexpr uint32_t kCount = 1000;  // not a multiple of the work-group size
    std::vector<uint32_t> input(kCount);
    std::iota(input.begin(), input.end(), 5u);
    engine::GpuBuffer in(context(), kCount * 4, vk::BufferUsageFlagBits::eStorageBuffer,
                         engine::GpuBuffer::Memory::HostVisible, "test input");
    engine::GpuBuffer out(context(), (kCount + 64) * 4, vk::BufferUsageFlagBits::eStorageBuffer,
                          engine::GpuBuffer::Memory::HostVisible, "test output");
    in.write(std::as_bytes(std::span(input)));
    std::vector<uint32_t> sentinel(kCount + 64, 0xDEADBEEFu);
    out.write(std::as_bytes(std::span(sentinel)));

    engine::ComputePipeline pipeline(context(), affine_fill_spv,
                                     {vk::DescriptorType::eStorageBuffer, vk::DescriptorType::eStorageBuffer}, 4,
                                     "affine fill");
    pipeline.bindBuffer(0, in);
    pipeline.bindBuffer(1, out);
    engine::submitAndWait(context(), [&](const vk::raii::CommandBuffer& commands) {
        pipeline.recordDispatch(commands, vk::Extent3D((kCount + 63) / 64, 1, 1),
                                std::as_bytes(std::span(&kCount, 1)));
    });
    std::vector<uint32_t> result(kCount + 64);
    out.read(std::as_writable_bytes(std::span(result)));
    for (uint32_t i = 0; i < kCount; ++i) ASSERT_EQ(result[i], input[i] * 3u + i) << "at " << i;
    for (uint32_t i = kCount; i < kCount + 64; ++i) ASSERT_EQ(result[i], 0xDEADBEEFu) << "written past count at " << i;
}

TEST_F(GpuResources, TimestampsMeasurePositiveDeviceTime) {
    if (context().timestampPeriodNs() <= 0.0) GTEST_SKIP() << "queue has no timestamps";
    engine::GpuTimer timer(context());
    engine::GpuBuffer buffer(context(), 1 << 20, vk::BufferUsageFlagBits::eTransferDst,
                             engine::GpuBuffer::Memory::HostVisible, "fill target");
    engine::submitAndWait(context(), [&](const vk::raii::CommandBuffer& commands) {
        timer.recordStart(commands);
        commands.fillBuffer(*buffer.buffer(), 0, VK_WHOLE_SIZE, 0x01020304u);
        timer.recordEnd(commands);
    });
    EXPECT_GE(timer.elapsedMs(), 0.0);
    EXPECT_EQ(static_cast<const uint32_t*>(buffer.mapped())[12345], 0x01020304u);
}

}  // namespace
