// The engine's display sequence, called in-process: the files of a 2-frame Immersive Cabin
// render, its pixels against each image rendered alone, cancellation keeping whole frames only,
// and hit images that lie on the iso surface and re-project to their own pixels.
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <gtest/gtest.h>
#include <zlib.h>

#include "conformal/cube_map_baker.h"
#include "engine/display/display.h"
#include "engine/output/png_reader.h"
#include "engine/render/raycaster.h"
#include "engine/render/volume_texture.h"
#include "engine/sequence/frame_sequence.h"
#include "tests/support/folder_compare.h"
#include "tests/support/gpu_test_fixture.h"
#include "volumes/analytic_phantom.h"
#include "volumes/brick_minmax.h"

namespace {

namespace fs = std::filesystem;
using engine::Eye;

fs::path tmp(const std::string& name) { return fs::path(CVC_TEST_TMP_DIR) / "sequence" / name; }

constexpr double kIsoHu = -480.0;

/// A tube phantom along z (lumen of radius 15 mm in 48^3 voxels of 1 mm) and a small
/// Immersive Cabin (its box, walls of 48 x 36 pixels) placed inside the lumen.
struct TubeScene {
    explicit TubeScene(const engine::GpuContext& context)
        : volume(makeVolume()), bricks(volumes::buildBrickMinMax(volume)), texture(context, volume),
          raycaster(context, volume, texture, bricks) {}

    static volumes::Volume makeVolume() {
        volumes::TubeSpec tube;
        tube.grid.dims = {48, 48, 48};
        tube.axisMm = {23.5, 23.5};
        tube.radiusMm = 15.0;
        return volumes::makeTubePhantom(tube);
    }

    volumes::Volume volume;
    volumes::BrickMinMax bricks;
    engine::VolumeTexture texture;
    engine::Raycaster raycaster;
};

engine::Display smallCabin(conformal::MapKind map) {
    engine::Display display = engine::displayPreset("ic5");
    for (auto& wall : display.walls) {
        wall.width = wall.name == engine::WallName::Floor ? 36 : 48;
        wall.height = 36;
    }
    display.map = map;
    return display;
}

engine::SequenceJob jobFor(const engine::Display& display, int frames) {
    engine::SequenceJob job;
    job.display = display;
    for (int i = 0; i < frames; ++i) {
        engine::CameraPose pose;
        pose.positionMm = {23.5 + 0.7 * i, 22.0, 12.0 + 4.0 * i};
        pose.forward = glm::normalize(glm::dvec3(0.1, 0.05, 1.0));
        pose.up = glm::normalize(glm::cross(glm::cross(pose.forward, glm::dvec3(0, 1, 0)), pose.forward));
        job.poses.push_back(pose);
    }
    job.mmPerMetre = 5.0;
    job.settings.isoHu = kIsoHu;
    job.warpMode = engine::WarpMode::Chord;
    job.mapSource = "test";
    return job;
}

engine::ScenePose scenePose(const engine::SequenceJob& job, int frame) {
    const auto& pose = job.poses[static_cast<std::size_t>(frame)];
    return {pose.positionMm, pose.forward, pose.up, job.mmPerMetre};
}

/// Trilinear HU of the volume at a point in volume millimetres (clamped to the grid).
double trilinearHu(const volumes::Volume& volume, const glm::dvec3& pointMm) {
    const glm::dvec3 g = pointMm / volume.spacingMm;
    int base[3];
    double frac[3];
    for (int a = 0; a < 3; ++a) {
        const double c = std::clamp(g[a], 0.0, volume.dims[a] - 1.0);
        base[a] = std::min(static_cast<int>(std::floor(c)), volume.dims[a] - 2);
        frac[a] = c - base[a];
    }
    double sum = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
        double weight = 1.0;
        int index[3];
        for (int a = 0; a < 3; ++a) {
            const int bit = (corner >> a) & 1;
            index[a] = base[a] + bit;
            weight *= bit ? frac[a] : 1.0 - frac[a];
        }
        sum += weight * volume.at(index[0], index[1], index[2]);
    }
    return sum;
}

/// The float xyz payload of a gzip NRRD written by writeHitPositionsNrrd.
std::vector<float> readGzipHits(const fs::path& path, int& width, int& height) {
    std::ifstream in(path, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t end = text.find("\n\n");
    if (end == std::string::npos) throw std::runtime_error("no header end");
    const std::string header = text.substr(0, end);
    if (header.find("encoding: gzip") == std::string::npos) throw std::runtime_error("not gzip");
    std::istringstream sizes(header.substr(header.find("sizes: ") + 7));
    int components = 0;
    sizes >> components >> width >> height;
    if (components != 3) throw std::runtime_error("not 3-vectors");
    std::vector<float> xyz(static_cast<std::size_t>(width) * height * 3);
    z_stream stream{};
    inflateInit2(&stream, 15 + 32);
    stream.next_in = reinterpret_cast<Bytef*>(text.data() + end + 2);
    stream.avail_in = static_cast<uInt>(text.size() - end - 2);
    stream.next_out = reinterpret_cast<Bytef*>(xyz.data());
    stream.avail_out = static_cast<uInt>(xyz.size() * sizeof(float));
    const int result = inflate(&stream, Z_FINISH);
    inflateEnd(&stream);
    if (result != Z_STREAM_END || stream.avail_out != 0) throw std::runtime_error("bad gzip payload");
    return xyz;
}

class FrameSequence : public testing_support::GpuTest {
protected:
    static void SetUpTestSuite() {
        GpuTest::SetUpTestSuite();
        conformal::BakeSettings bake;
        bake.box.size = smallCabin(conformal::MapKind::Conformal).boxSizeM;
        bake.size = 32;
        bake.mesh.resolution = 24;
        bake.kind = conformal::MapKind::Conformal;
        sMap = std::make_unique<conformal::CubeMap>(conformal::bakeCubeMap(bake));
    }
    static inline std::unique_ptr<conformal::CubeMap> sMap;
};

TEST_F(FrameSequence, WritesEveryFileAndThePixelsOfEachImageRenderedAlone) {
    TubeScene scene(context());
    scene.raycaster.setCubeMap(sMap->size, sMap->rgba);
    engine::SequenceJob job = jobFor(smallCabin(conformal::MapKind::Conformal), 2);
    job.isWritingBeforeAfter = true;
    job.isWritingHits = true;
    const fs::path out = tmp("two_frames");
    fs::remove_all(out);

    std::map<int, std::vector<engine::WallImage>> inMemory;
    std::vector<std::pair<int, int>> progress;
    engine::SequenceHooks hooks;
    hooks.onFrame = [&](int frame, const std::vector<engine::WallImage>& images) { inMemory[frame] = images; };
    hooks.onProgress = [&](int done, int total) { progress.emplace_back(done, total); };
    const engine::SequenceSummary summary = engine::renderSequence(scene.raycaster, job, {out.string()}, hooks);
    EXPECT_EQ(summary.framesRendered, 2);
    EXPECT_EQ(progress, (std::vector<std::pair<int, int>>{{0, 2}, {1, 2}, {2, 2}}));
    EXPECT_TRUE(fs::exists(out / "render.json"));
    ASSERT_EQ(inMemory.size(), 2u);

    engine::RenderSettings alone = job.settings;
    alone.isWritingHits = true;
    for (int frame = 0; frame < 2; ++frame) {
        const fs::path frameFolder = out / engine::frameFolderName(frame);
        EXPECT_TRUE(fs::exists(frameFolder / "sheet.png"));
        EXPECT_TRUE(fs::exists(frameFolder / "before_after.png"));
        ASSERT_EQ(inMemory[frame].size(), 10u);
        for (const engine::WallImage& wall : inMemory[frame]) {
            const std::string name = engine::wallNameText(wall.wall);
            const fs::path png = frameFolder / engine::eyeText(wall.eye) / (name + ".png");
            ASSERT_TRUE(fs::exists(png)) << png;
            ASSERT_TRUE(fs::exists(frameFolder / engine::eyeText(wall.eye) / (name + "_hits.nrrd")));
            // The same request through the single-image path gives the same pixels, in memory and on disk.
            const auto view = engine::wallView(job.display, wall.wall, wall.eye, scenePose(job, frame), job.warpMode);
            const engine::RenderedImage single = scene.raycaster.render(view.rays, alone, view.warp);
            EXPECT_EQ(single.rgba, wall.image.rgba) << png;
            EXPECT_EQ(single.hitMm, wall.image.hitMm) << png;
            const colon::RgbaImage file = engine::readPng(png.string());
            EXPECT_EQ(file.width, single.width);
            EXPECT_EQ(file.rgba, single.rgba) << png;
        }
    }
    // No hidden partial folders are left behind.
    for (const auto& entry : fs::directory_iterator(out)) {
        EXPECT_NE(entry.path().filename().string().front(), '.') << entry.path();
    }
}

TEST_F(FrameSequence, CancellingKeepsFinishedFramesOnlyAndResumeCompletesTheRest) {
    TubeScene scene(context());
    engine::SequenceJob job = jobFor(smallCabin(conformal::MapKind::None), 3);
    const fs::path out = tmp("cancelled");
    fs::remove_all(out);

    // Cancelled after the first image of the first frame was written: no frame is kept.
    // Atomic: the hook is polled from the image workers too (ThreadSanitizer found it racing).
    std::atomic<int> polls = 0;
    engine::SequenceHooks early;
    early.isCancelled = [&] { return ++polls > 3; };  // frame 0 submitted, frame 1 submitted, frame 0's first image
    EXPECT_THROW(engine::renderSequence(scene.raycaster, job, {out.string()}, early), engine::SequenceCancelled);
    for (const auto& entry : fs::directory_iterator(out)) {
        EXPECT_EQ(entry.path().filename(), "render.json") << "left behind: " << entry.path();
    }

    // Cancelled once the first frame is finished: that frame stays, whole; the rest is not there.
    std::atomic<bool> stop{false};
    engine::SequenceHooks late;
    late.isCancelled = [&] { return stop.load(); };
    late.onProgress = [&](int done, int) { stop = done >= 1; };
    EXPECT_THROW(engine::renderSequence(scene.raycaster, job, {out.string(), true, false}, late),
                 engine::SequenceCancelled);
    EXPECT_TRUE(fs::exists(out / "frame_0000" / "sheet.png"));
    EXPECT_TRUE(fs::exists(out / "frame_0000" / "right" / "floor.png"));
    EXPECT_FALSE(fs::exists(out / "frame_0001"));
    EXPECT_FALSE(fs::exists(out / ".frame_0001.partial"));
    EXPECT_FALSE(fs::exists(out / "frame_0002"));

    // Resuming renders the two missing frames and keeps the finished one.
    const auto kept = fs::last_write_time(out / "frame_0000" / "sheet.png");
    const engine::SequenceSummary resumed = engine::renderSequence(scene.raycaster, job, {out.string(), false, true});
    EXPECT_EQ(resumed.framesKept, 1);
    EXPECT_EQ(resumed.framesRendered, 2);
    EXPECT_TRUE(fs::exists(out / "frame_0002" / "left" / "front.png"));
    EXPECT_EQ(fs::last_write_time(out / "frame_0000" / "sheet.png"), kept);
}

// A run stopped while rank 0 had not yet written another rank's sheet leaves that frame's
// images whole in ".frame_NNNN.written": resuming composes its sheet from them instead of
// rendering it again, while a ".partial" frame is rendered again. The folder ends byte for
// byte as a run that never stopped wrote it.
TEST_F(FrameSequence, ResumeFinishesAWrittenFrameFromItsImagesAndRendersAPartialOne) {
    TubeScene scene(context());
    scene.raycaster.setCubeMap(sMap->size, sMap->rgba);
    engine::SequenceJob job = jobFor(smallCabin(conformal::MapKind::Conformal), 3);
    job.isWritingBeforeAfter = true;
    const fs::path whole = tmp("never_stopped");
    const fs::path out = tmp("stopped_with_written_frame");
    fs::remove_all(whole);
    fs::remove_all(out);
    engine::renderSequence(scene.raycaster, job, {whole.string()});
    fs::copy(whole, out, fs::copy_options::recursive);
    // Frame 1 as another rank leaves it: every image, no sheet. Frame 2 half written.
    fs::rename(out / "frame_0001", out / ".frame_0001.written");
    fs::remove(out / ".frame_0001.written" / "sheet.png");
    fs::rename(out / "frame_0002", out / ".frame_0002.partial");
    fs::remove(out / ".frame_0002.partial" / "right" / "floor.png");

    std::vector<std::pair<int, int>> progress;
    engine::SequenceHooks hooks;
    hooks.onProgress = [&](int done, int total) { progress.emplace_back(done, total); };
    const engine::SequenceSummary resumed =
        engine::renderSequence(scene.raycaster, job, {out.string(), false, true}, hooks);
    EXPECT_EQ(resumed.framesKept, 1);
    EXPECT_EQ(resumed.framesFinishedFromImages, std::vector<int>{1});
    EXPECT_EQ(resumed.framesLeftHalfWritten, std::vector<int>{2});
    EXPECT_EQ(resumed.framesRendered, 1);
    EXPECT_EQ(progress, (std::vector<std::pair<int, int>>{{1, 3}, {2, 3}, {3, 3}}));
    testing_support::expectSameFolders(whole, out);
}

TEST_F(FrameSequence, HitsLieOnTheIsoSurfaceAndReprojectToTheirPixelsMissesAreNaN) {
    TubeScene scene(context());
    engine::SequenceJob job = jobFor(smallCabin(conformal::MapKind::None), 1);
    job.isWritingHits = true;
    // Look across the tube so that some rays leave through its open end and miss.
    job.poses[0].positionMm = {23.5, 23.5, 40.0};
    const fs::path out = tmp("hits");
    fs::remove_all(out);
    std::vector<engine::WallImage> images;
    engine::SequenceHooks hooks;
    hooks.onFrame = [&](int, const std::vector<engine::WallImage>& frame) { images = frame; };
    engine::renderSequence(scene.raycaster, job, {out.string()}, hooks);
    ASSERT_EQ(images.size(), 10u);

    int hits = 0, misses = 0;
    double worstHu = 0.0, worstPixel = 0.0;
    for (const engine::WallImage& wall : images) {
        int width = 0, height = 0;
        const std::vector<float> file = readGzipHits(
            out / "frame_0000" / engine::eyeText(wall.eye) / (engine::wallNameText(wall.wall) + "_hits.nrrd"), width,
            height);
        ASSERT_EQ(width, wall.image.width);
        ASSERT_EQ(height, wall.image.height);
        const auto view = engine::wallView(job.display, wall.wall, wall.eye, scenePose(job, 0), job.warpMode);
        const glm::dvec3 normal = glm::normalize(glm::cross(view.rays.wallUMm, view.rays.wallVMm));
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                const std::size_t p = static_cast<std::size_t>(y) * width + x;
                const float* memory = &wall.image.hitMm[4 * p];
                const float* written = &file[3 * p];
                if (memory[3] <= 0.0f) {
                    ++misses;
                    EXPECT_TRUE(std::isnan(written[0]) && std::isnan(written[1]) && std::isnan(written[2]));
                    continue;
                }
                ++hits;
                for (int c = 0; c < 3; ++c) ASSERT_EQ(written[c], memory[c]);
                const glm::dvec3 hit(memory[0], memory[1], memory[2]);
                worstHu = std::max(worstHu, std::abs(trilinearHu(scene.volume, hit) - kIsoHu));
                // Central projection of the hit from the eye onto the wall's plane: its own pixel.
                const glm::dvec3 toHit = hit - view.rays.eyeMm;
                const double along = glm::dot(view.rays.wallOriginMm - view.rays.eyeMm, normal) / glm::dot(toHit, normal);
                const glm::dvec3 onWall = view.rays.eyeMm + along * toHit - view.rays.wallOriginMm;
                const double u = glm::dot(onWall, view.rays.wallUMm) / glm::dot(view.rays.wallUMm, view.rays.wallUMm);
                const double v = glm::dot(onWall, view.rays.wallVMm) / glm::dot(view.rays.wallVMm, view.rays.wallVMm);
                worstPixel = std::max({worstPixel, std::abs(u * width - (x + 0.5)), std::abs(v * height - (y + 0.5))});
            }
        }
    }
    EXPECT_GT(hits, 1000);
    EXPECT_GT(misses, 20);
    // The wall rises from -1000 to +40 HU over 2 mm. The default 2 bisection steps of a 1-voxel
    // step leave a quarter-voxel bracket, and the linear interpolation in it is nearly exact
    // there (lavapipe: 1 HU); a device's coarser trilinear weights may add several HU.
    EXPECT_LT(worstHu, 25.0);
    EXPECT_LT(worstPixel, 0.01);
}

}  // namespace

namespace {

TEST(FrameSequenceShare, FramesAreDealtRoundRobinOverThePendingOnesAndWallsGiveEveryRankEachFrame) {
    const std::vector<int> pending = {0, 2, 3, 5, 8};  // 1, 4, 6 and 7 were kept by an earlier run
    engine::SequenceShare share;
    share.ranks = 2;
    EXPECT_EQ(engine::framesOfRank(pending, share, 0), (std::vector<int>{0, 3, 8}));
    EXPECT_EQ(engine::framesOfRank(pending, share, 1), (std::vector<int>{2, 5}));
    share.ranks = 7;  // more ranks than frames: the last ones have none
    EXPECT_EQ(engine::framesOfRank(pending, share, 4), (std::vector<int>{8}));
    EXPECT_TRUE(engine::framesOfRank(pending, share, 6).empty());
    share.distribution = engine::Distribution::Walls;
    EXPECT_EQ(engine::framesOfRank(pending, share, 3), pending);
    share.ranks = 1;
    share.distribution = engine::Distribution::Frames;
    EXPECT_EQ(engine::framesOfRank(pending, share, 0), pending);
}

}  // namespace
