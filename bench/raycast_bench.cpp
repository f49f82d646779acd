/// @brief `cvc_bench ceiling`: the rate of plain trilinear volume sampling on a device, the
/// ceiling a ray caster's sampling rate is measured against (scripts/bench_raycaster.py).
#include <algorithm>
#include <iostream>
#include <vector>

#include <CLI/CLI.hpp>

#include "engine/command_submission.h"
#include "engine/compute_pipeline.h"
#include "engine/gpu_buffer.h"
#include "engine/gpu_context.h"
#include "engine/volume_texture.h"
#include "sampling_ceiling_spv.h"
#include "volumes/load_volume.h"

namespace {

struct CeilingPush {
    uint32_t width;
    uint32_t height;
    uint32_t stepsPerRay;
    float stepTex;
};

void runCeiling(const std::string& volumePath, int size, int steps, int runs, const std::string& device) {
    const volumes::Volume volume = volumes::loadVolume(volumePath);
    engine::GpuContext context(engine::GpuContextOptions{false, device});
    engine::VolumeTexture texture(context, volume);
    engine::ComputePipeline pipeline(
        context, sampling_ceiling_spv,
        {vk::DescriptorType::eCombinedImageSampler, vk::DescriptorType::eStorageBuffer}, sizeof(CeilingPush),
        "sampling ceiling");
    const auto pixels = static_cast<vk::DeviceSize>(size) * static_cast<vk::DeviceSize>(size);
    engine::GpuBuffer sums(context, pixels * 4, vk::BufferUsageFlagBits::eStorageBuffer,
                           engine::GpuBuffer::Memory::DeviceLocal, "ceiling sums");
    pipeline.bindSampledImage(0, texture.image(), texture.sampler());
    pipeline.bindBuffer(1, sums);
    // Half a voxel per step along the largest axis, as the ray caster's default.
    const int longest = std::max({volume.dims[0], volume.dims[1], volume.dims[2]});
    const CeilingPush push{static_cast<uint32_t>(size), static_cast<uint32_t>(size), static_cast<uint32_t>(steps),
                           0.5f / static_cast<float>(longest)};
    std::vector<double> ms;
    for (int run = 0; run < runs; ++run) {
        engine::GpuTimer timer(context);
        engine::submitAndWait(context, [&](const vk::raii::CommandBuffer& commands) {
            timer.recordStart(commands);
            const auto groups = static_cast<uint32_t>((size + 7) / 8);
            pipeline.recordDispatch(commands, vk::Extent3D(groups, groups, 1), std::as_bytes(std::span(&push, 1)));
            timer.recordEnd(commands);
        });
        ms.push_back(timer.elapsedMs());
    }
    std::sort(ms.begin(), ms.end());
    const double median = ms[ms.size() / 2];
    const double samples = static_cast<double>(pixels) * steps;
    std::cout << "{\"device\": \"" << context.deviceName() << "\", \"rays\": " << pixels << ", \"steps_per_ray\": " << steps
              << ", \"median_ms\": " << median << ", \"samples_per_second\": " << samples / (median * 1e-3) << "}\n";
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App program{"conformal-vc benchmarks"};
    program.require_subcommand(1);
    std::string volumePath, device;
    int size = 1024, steps = 100, runs = 5;
    CLI::App* ceiling = program.add_subcommand("ceiling", "Samples per second of plain trilinear sampling");
    ceiling->add_option("volume", volumePath, "Volume file")->required();
    ceiling->add_option("--size", size, "Rays per image side")->capture_default_str();
    ceiling->add_option("--steps", steps, "Samples per ray")->capture_default_str();
    ceiling->add_option("--runs", runs, "Repetitions (the median is reported)")->capture_default_str();
    ceiling->add_option("--device", device, "Vulkan device");
    ceiling->callback([&] { runCeiling(volumePath, size, steps, runs, device); });
    try {
        program.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return program.exit(e);
    } catch (const std::exception& e) {
        std::cerr << "cvc_bench: error: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
