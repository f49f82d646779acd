/// @brief `cvc_bench ceiling`: the rate of plain trilinear volume sampling on a device, the
/// ceiling a ray caster's sampling rate is measured against (scripts/bench/bench_raycaster.py).
/// `cvc_bench png`: the time and size of PNG encodings of a rendered wall, to choose the
/// display sequence's settings (scripts/bench/bench_flythrough.sh).
/// `cvc_bench warp`: the warp's own cost, through an identity cube map (bench/warp_bench.h,
/// scripts/bench/bench_warp_cost.sh).
/// `cvc_bench skipping`: empty-space skipping's cost or gain on one pinhole view, per step size
/// (bench/skipping_bench.h, scripts/bench/bench_march.sh).
/// `cvc_bench view`: a pinhole view timed as the VTK yardstick times VTK (bench/view_bench.h).
/// `cvc_bench stereo`: the stereo eyes' warps, time against error (bench/stereo_bench.h,
/// scripts/bench/bench_stereo.sh).
/// `cvc_bench polyline`: how far the chord and the polyline stray from a stereo eye's bent ray
/// (bench/polyline_study.h).
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <vector>

#include <CLI/CLI.hpp>
#include <png.h>

#include "bench/polyline_study.h"
#include "bench/skipping_bench.h"
#include "bench/stereo_bench.h"
#include "bench/view_bench.h"
#include "bench/warp_bench.h"
#include "engine/core/command_submission.h"
#include "engine/core/compute_pipeline.h"
#include "engine/core/gpu_buffer.h"
#include "engine/core/gpu_context.h"
#include "engine/output/png_writer.h"
#include "engine/render/volume_texture.h"
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

/// Encodes `imagePath`'s pixels with each filter and zlib level, `runs` times each, and prints
/// one JSON line per setting: median milliseconds and bytes.
void runPng(const std::string& imagePath, int runs) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, imagePath.c_str())) throw std::runtime_error(imagePath + ": " + image.message);
    image.format = PNG_FORMAT_RGBA;
    std::vector<uint8_t> rgba(PNG_IMAGE_SIZE(image));
    if (!png_image_finish_read(&image, nullptr, rgba.data(), 0, nullptr)) throw std::runtime_error(imagePath + ": " + image.message);
    const auto width = static_cast<int>(image.width);
    const auto height = static_cast<int>(image.height);
    const std::filesystem::path out = std::filesystem::temp_directory_path() / "cvc_bench_png.png";
    const std::pair<engine::PngFilter, const char*> filters[] = {{engine::PngFilter::None, "none"},
                                                                 {engine::PngFilter::Sub, "sub"},
                                                                 {engine::PngFilter::Up, "up"},
                                                                 {engine::PngFilter::Paeth, "paeth"},
                                                                 {engine::PngFilter::Adaptive, "adaptive"}};
    for (const auto& [filter, name] : filters) {
        for (int level : {1, 3, 6}) {
            std::vector<double> ms;
            for (int run = 0; run < runs; ++run) {
                const auto start = std::chrono::steady_clock::now();
                engine::writePng(out.string(), width, height, rgba, true, {level, filter});
                ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
            }
            std::sort(ms.begin(), ms.end());
            std::cout << "{\"image\": \"" << imagePath << "\", \"filter\": \"" << name << "\", \"zlib_level\": " << level
                      << ", \"median_ms\": " << ms[ms.size() / 2] << ", \"bytes\": " << std::filesystem::file_size(out)
                      << "}\n";
        }
    }
    std::filesystem::remove(out);
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
    std::string imagePath;
    CLI::App* png = program.add_subcommand("png", "Time and size of PNG encodings of an image (filters x zlib levels)");
    png->add_option("image", imagePath, "A PNG, e.g. a rendered wall")->required();
    png->add_option("--runs", runs, "Repetitions (the median is reported)")->capture_default_str();
    png->callback([&] { runPng(imagePath, runs); });
    bench::WarpBenchRequest warp;
    CLI::App* warpCommand = program.add_subcommand(
        "warp", "Device time of a stereo display frame through its map, an identity cube map and no warp");
    bench::addDisplayFrameOptions(warpCommand, warp.frame);
    warpCommand->add_option("--scale", warp.mmPerMetre, "Scene millimetres per CAVE metre")->capture_default_str();
    warpCommand->callback([&] { bench::runWarpBench(warp); });
    bench::StereoBenchRequest stereo;
    CLI::App* stereoCommand = program.add_subcommand(
        "stereo", "A stereo display frame with each warp (chord, eye-centred, polyline, exact): device time and difference to exact");
    bench::addDisplayFrameOptions(stereoCommand, stereo.frame);
    stereoCommand->add_option("--scale", stereo.mmPerMetre, "Scene millimetres per CAVE metre, one or more")
        ->delimiter(',')
        ->capture_default_str();
    stereoCommand->callback([&] { bench::runStereoBench(stereo); });
    bench::PolylineStudyRequest polyline;
    CLI::App* polylineCommand = program.add_subcommand(
        "polyline", "How far the chord and the polyline stray from a stereo eye's bent ray, in pixel footprints");
    polylineCommand->add_option("--display", polyline.display, "Display preset or JSON")->capture_default_str();
    polylineCommand->add_option("--scale", polyline.mmPerMetre, "Scene millimetres per CAVE metre, one or more")
        ->delimiter(',')
        ->capture_default_str();
    polylineCommand->add_option("--map-size", polyline.mapSize, "Cube-map texels per face edge")->capture_default_str();
    polylineCommand->add_option("--directions", polyline.directions, "Directions over the sphere")->capture_default_str();
    polylineCommand->callback([&] { bench::runPolylineStudy(polyline); });
    bench::SkippingBenchRequest skipping;
    CLI::App* skippingCommand = program.add_subcommand(
        "skipping", "Device time of a pinhole view without skipping, with looks decided per tile, and in every tile");
    bench::addPinholeSceneOptions(skippingCommand, skipping.scene);
    skippingCommand->add_option("--steps", skipping.stepsVoxels, "Step sizes in voxels")->delimiter(',');
    skippingCommand->add_option("--runs", skipping.runs, "Repetitions of each variant (medians are reported)")
        ->capture_default_str();
    skippingCommand->callback([&] { bench::runSkippingBench(skipping); });
    bench::ViewBenchRequest view;
    CLI::App* viewCommand = program.add_subcommand(
        "view", "Device time of a pinhole view timed as ../shared/bench/vtk/render.py times VTK's");
    bench::addPinholeSceneOptions(viewCommand, view.scene);
    viewCommand->add_option("--step", view.stepVoxels, "Step in voxels")->check(CLI::Range(0.01, 16.0))
        ->capture_default_str();
    viewCommand->add_flag("--no-skip{false}", view.isSkipping, "Turn off empty-space skipping");
    viewCommand->add_option("--skip-cell", view.skipCellVoxels, "Edge in voxels of the empty-space map's cells")
        ->check(CLI::Range(1, 64))->capture_default_str();
    viewCommand->add_option("--filter", view.filter, "trilinear or tricubic")
        ->check(CLI::IsMember({"trilinear", "tricubic"}))->capture_default_str();
    viewCommand->add_option("--refine", view.refinementSteps, "Iso mode: bisection steps refining each hit")
        ->capture_default_str();
    viewCommand->add_flag("--adaptive", view.isAdaptive, "Lengthen steps where a pixel covers more than a voxel");
    viewCommand->add_option("--repeats", view.repeats, "Timed renders after the first (the median is reported)")
        ->capture_default_str();
    viewCommand->callback([&] { bench::runViewBench(view); });
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
