// Bad input given to `cvc`: one clear line on stderr naming the problem, a non-zero exit, no
// crash, and nothing the user had overwritten.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/run_program.h"
#include "volumes/analytic_phantom.h"
#include "volumes/nrrd_io.h"

namespace {

namespace fs = std::filesystem;
using testing_support::lineCount;
using testing_support::readWholeFile;
using testing_support::runCvc;

fs::path tmp(const std::string& name) { return fs::path(CVC_TEST_TMP_DIR) / name; }

/// A small valid NRRD volume to damage in various ways.
fs::path writeSmallVolume(const std::string& name) {
    volumes::BallSpec spec;
    spec.grid.dims = {16, 16, 16};
    spec.centreMm = glm::dvec3(7.5);
    spec.radiusMm = 5.0;
    const fs::path path = tmp(name);
    volumes::writeNrrd(volumes::makeBallPhantom(spec), path.string(), true);
    return path;
}

void expectOneLineError(const testing_support::ProgramRun& run, const std::string& mustMention) {
    EXPECT_NE(run.exitCode, 0);
    EXPECT_EQ(lineCount(run.err), 1) << run.err;
    EXPECT_EQ(run.err.rfind("cvc: error: ", 0), 0u) << run.err;
    EXPECT_NE(run.err.find(mustMention), std::string::npos) << run.err;
}

TEST(CliErrors, MissingVolumeFile) {
    const auto run = runCvc("render " + tmp("does_not_exist.nrrd").string() + " -o " + tmp("x.png").string() + " --force");
    expectOneLineError(run, "does_not_exist.nrrd: no such file or folder");
}

TEST(CliErrors, TruncatedNrrd) {
    const fs::path good = writeSmallVolume("truncate_me.nrrd");
    const std::string bytes = readWholeFile(good);
    const fs::path bad = tmp("truncated.nrrd");
    std::ofstream(bad, std::ios::binary) << bytes.substr(0, bytes.size() - 1000);
    const auto run = runCvc("render " + bad.string() + " -o " + tmp("x.png").string() + " --force");
    expectOneLineError(run, "truncated.nrrd: holds");
    EXPECT_NE(run.err.find("truncated"), std::string::npos);
}

TEST(CliErrors, HeaderDisagreesWithDataSize) {
    const fs::path good = writeSmallVolume("resize_me.nrrd");
    std::string bytes = readWholeFile(good);
    const auto sizes = bytes.find("sizes: 16 16 16");
    ASSERT_NE(sizes, std::string::npos);
    bytes.replace(sizes, 15, "sizes: 16 16 15");  // one slice fewer than the data holds
    const fs::path bad = tmp("wrong_sizes.nrrd");
    std::ofstream(bad, std::ios::binary) << bytes;
    const auto run = runCvc("render " + bad.string() + " -o " + tmp("x.png").string() + " --force");
    expectOneLineError(run, "wrong_sizes.nrrd: holds 8192 bytes of voxel data, the header's sizes and type call for 7680");
}

TEST(CliErrors, GarbageAndAbsurdHeaders) {
    const fs::path garbage = tmp("garbage.nrrd");
    std::ofstream(garbage, std::ios::binary) << "this is not a volume\n";
    expectOneLineError(runCvc("render " + garbage.string() + " -o " + tmp("x.png").string() + " --force"),
                       "not a NRRD file");

    const fs::path huge = tmp("huge.nrrd");
    std::ofstream(huge, std::ios::binary) << "NRRD0004\ntype: int16\ndimension: 3\nsizes: 100000 100000 100000\n"
                                             "encoding: raw\n\n";
    expectOneLineError(runCvc("render " + huge.string() + " -o " + tmp("x.png").string() + " --force"),
                       "size 100000 along axis 0 is outside 1..4096");

    const fs::path spacing = tmp("spacing.nrrd");
    std::ofstream(spacing, std::ios::binary)
        << "NRRD0004\ntype: int16\ndimension: 3\nsizes: 2 2 2\nspace: left-posterior-superior\n"
           "space directions: (1e9,0,0) (0,1,0) (0,0,1)\nencoding: raw\n\n"
        << std::string(16, '\0');
    expectOneLineError(runCvc("render " + spacing.string() + " -o " + tmp("x.png").string() + " --force"),
                       "voxel spacing along axis 0 is 1e+09 mm");
}

TEST(CliErrors, NaNVoxelsAreRejected) {
    const fs::path path = tmp("nan.nrrd");
    std::ofstream out(path, std::ios::binary);
    out << "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nencoding: raw\nendian: little\n\n";
    const float values[8] = {0, 1, 2, 3, std::numeric_limits<float>::quiet_NaN(), 5, 6, 7};
    out.write(reinterpret_cast<const char*>(values), sizeof(values));
    out.close();
    expectOneLineError(runCvc("render " + path.string() + " -o " + tmp("x.png").string() + " --force"),
                       "voxel 4 is not a finite number");
}

TEST(CliErrors, NoVulkanDriver) {
    const fs::path volume = writeSmallVolume("no_driver.nrrd");
    const auto run = runCvc("render " + volume.string() + " -o " + tmp("no_driver.png").string() + " --force",
                            "VK_DRIVER_FILES=/nonexistent/icd.json VK_ICD_FILENAMES=/nonexistent/icd.json");
    expectOneLineError(run, "Vulkan");
    EXPECT_FALSE(fs::exists(tmp("no_driver.png")));
}

TEST(CliErrors, BadStepAndLightDistanceAreRefusedNotReplacedByTheDefault) {
    const fs::path volume = writeSmallVolume("bad_settings.nrrd");
    const fs::path out = tmp("bad_settings.png");
    for (const char* step : {"0", "-1", "nan"}) {
        fs::remove(out);
        expectOneLineError(runCvc("render " + volume.string() + " --size 8x8 --step " + step + " -o " + out.string()),
                           "step must be 0.01..8 voxels");
        EXPECT_FALSE(fs::exists(out)) << "--step " << step;
    }
    expectOneLineError(runCvc("render " + volume.string() + " --size 8x8 --light-distance -5 -o " + out.string()),
                       "light half distance must be >= 0");
    EXPECT_FALSE(fs::exists(out));
}

TEST(CliErrors, UnknownDeviceNamesEveryCandidate) {
    const fs::path volume = writeSmallVolume("no_such_device.nrrd");
    const auto run = runCvc("render " + volume.string() + " -o " + tmp("x.png").string() +
                            " --force --device no-such-gpu-anywhere");
    expectOneLineError(run, "does not match the requested device 'no-such-gpu-anywhere'");
}

TEST(CliErrors, ExistingOutputIsNotOverwrittenWithoutForce) {
    const fs::path volume = writeSmallVolume("keep.nrrd");
    const fs::path existing = tmp("keep_me.png");
    std::ofstream(existing) << "precious";
    expectOneLineError(runCvc("render " + volume.string() + " -o " + existing.string()), "exists already");
    EXPECT_EQ(readWholeFile(existing), "precious");
    expectOneLineError(runCvc("phantom -o " + volume.string()), "exists already");
}

TEST(CliErrors, UnwritableOutputFolder) {
    const fs::path volume = writeSmallVolume("unwritable.nrrd");
    expectOneLineError(runCvc("render " + volume.string() + " -o " + tmp("missing_folder/x.png").string()),
                       "does not exist");
}

TEST(CliErrors, BakeRefusesADisplayWithoutAMissingWall) {
    const fs::path out = tmp("cave6.cvcm");
    fs::remove(out);
    expectOneLineError(runCvc("bake --display cave6 --size 16 -o " + out.string(),
                              "CVC_CACHE_DIR=" + tmp("bake_cave6_cache").string()),
                       "display 'cave6' has no missing wall: there is no map to bake");
    EXPECT_FALSE(fs::exists(out));
}

TEST(CliErrors, RenderRefusesACubeMapBakedForAnotherDisplay) {
    // A linear map (baked in milliseconds) for the 2.4 m cube, used with the Immersive Cabin.
    const std::string cache = "CVC_CACHE_DIR=" + tmp("cube_map_mismatch_cache").string();
    const fs::path cubeBox = tmp("cube_box_linear.cvcm");
    const auto bake = runCvc("bake --box 2.4 2.4 2.4 --map linear --size 16 --force -o " + cubeBox.string(), cache);
    ASSERT_EQ(bake.exitCode, 0) << bake.err;
    EXPECT_NE(bake.out.find("wrote linear cube map 16^2 x 6 for display 'custom', box 2.4 x 2.4 x 2.4 m"),
              std::string::npos)
        << bake.out;

    const fs::path volume = writeSmallVolume("cube_map_mismatch.nrrd");
    const std::string render = "render " + volume.string() +
                               " --display ic5 --position 7.5,7.5,4 --look-at 7.5,7.5,12 --up 0,1,0 --force" +
                               " --cube-map " + cubeBox.string() + " -o " + tmp("cube_map_mismatch").string();
    expectOneLineError(runCvc(render + " --map linear", cache),
                       "cube map " + cubeBox.string() +
                           " was baked for box 2.4 x 2.4 x 2.4 m, the display 'ic5' has 2.95 x 2.21 x 2.95 m");
    // --map is applied first, then the file's kind is checked against it.
    expectOneLineError(runCvc(render + " --map conformal", cache),
                       "holds the linear map, the display 'ic5' asks for conformal");
    // Without a map there is nothing to bend the rays through: the file is refused outright.
    expectOneLineError(runCvc(render + " --map none", cache), "--cube-map bends the rays through a map");
    EXPECT_FALSE(fs::exists(tmp("cube_map_mismatch") / "frame_0000"));
}

TEST(CliErrors, CubeMapIsForDisplayRenders) {
    const fs::path volume = writeSmallVolume("pinhole_cube_map.nrrd");
    expectOneLineError(runCvc("render " + volume.string() + " --cube-map x.cvcm --force -o " +
                              tmp("pinhole_cube_map.png").string()),
                       "--cube-map is for display renders (--display)");
}

/// Options that the request makes meaningless are refused, each with its reason, before any
/// work: a user who typed them expects them to matter.
TEST(CliErrors, OptionsThatDoNotApplyAreRefusedNotIgnored) {
    const fs::path volume = writeSmallVolume("not_applying.nrrd");
    const fs::path picture = tmp("not_applying.png");
    const std::string pinhole = "render " + volume.string() + " --force -o " + picture.string() + " ";
    const std::pair<std::string, std::string> pinholeCases[] = {
        {"--path x.json", "--path is for display renders"},
        {"--warp exact", "--warp is for display renders"},
        {"--candidates c.json", "--candidates is for display renders"},
        {"--resume", "--resume is for display renders"},
        {"--map-size 64", "--map-size is for display renders"},
        {"--polyp 1", "--polyp is for display renders"},
        {"--mode composite --iso -300", "--iso is for --mode iso"},
        {"--mode composite --refine 2", "--refine is for --mode iso"},
        {"--tf bone", "--tf is for --mode composite"},
        {"--early-termination 0.9", "--early-termination is for --mode composite"},
        {"--no-skip --skip-cell 4", "--skip-cell sets how empty space is skipped, which --no-skip turns off"},
        {"--no-skip --no-start-pass", "--no-start-pass sets how empty space is skipped, which --no-skip turns off"},
        {"--skip-bent-rays", "--skip-bent-rays is for --warp exact"},
        {"--filter tricubic --gradient central", "the tricubic filter always shades with B-spline normals"},
    };
    for (const auto& [given, reason] : pinholeCases) {
        fs::remove(picture);
        expectOneLineError(runCvc(pinhole + given), reason);
        EXPECT_FALSE(fs::exists(picture)) << given;
    }

    const fs::path folder = tmp("not_applying_frames");
    fs::remove_all(folder);
    const std::string display = "render " + volume.string() + " --display ic5 --force -o " + folder.string() + " ";
    const std::string pose = "--position 7.5,7.5,4 --look-at 7.5,7.5,12 ";
    const std::pair<std::string, std::string> displayCases[] = {
        {pose + "--size 64x64", "--size sets the pinhole camera"},
        {pose + "--fov 60", "--fov sets the pinhole camera"},
        {pose + "--stats", "--stats counts the fetches of a pinhole view"},
        {pose + "--frames 3", "--frames needs --path"},
        {pose + "--retrograde", "--retrograde needs --path"},
        {pose + "--path-step 4", "--path-step needs --path"},
        {"--path x.json --position 1,2,3", "--position sets a single pose"},
        {"--path x.json --polyp 0 --frames 2", "--frames counts the frames of a fly-through"},
        {"--path x.json --polyp-elevation 30", "--polyp-elevation needs --polyp"},
        {pose + "--candidates c.json", "--candidates needs --path"},
        {"--path x.json --at-candidates", "--at-candidates needs --candidates"},
        {"--path x.json --polyp 0 --candidates c.json --at-candidates", "--at-candidates poses a frame per candidate"},
        {"--path x.json --polyp 0 --candidates c.json", "--candidates places them on a fly-through's frames"},
        {"--path x.json --candidates c.json --retrograde", "--retrograde reverses the frames cvc candidates placed"},
        {"--path x.json --candidates c.json --at-candidates --frames 2",
         "--frames counts the frames of a fly-through; --at-candidates"},
        {pose + "--cube-map x.cvcm --map-size 64", "--map-size is the bake's size"},
        {pose + "--map none --warp exact", "--warp bends the rays through a map"},
        {pose + "--map none --map-size 64", "--map-size bends the rays through a map"},
    };
    for (const auto& [given, reason] : displayCases) {
        expectOneLineError(runCvc(display + given), reason);
        EXPECT_FALSE(fs::exists(folder / "frame_0000")) << given;
    }
    // A display whose own map is none, with no --map given.
    expectOneLineError(runCvc("render " + volume.string() + " --display forward --force -o " + folder.string() + " " +
                              pose + "--warp exact"),
                       "--warp bends the rays through a map, and forward");

    const std::string coverage = "coverage " + volume.string() + " --path x.json --force -o " + folder.string() + " ";
    expectOneLineError(runCvc(coverage + "--compare --display ic6"), "--display is set by each row of --compare");
    expectOneLineError(runCvc(coverage + "--display forward --map-size 64"), "--map-size bends the rays through a map");
}

/// A value CLI11 itself refuses (out of a range, not a number, an unknown option) is one line too.
TEST(CliErrors, ParseErrorsAreOneLine) {
    const fs::path volume = writeSmallVolume("parse_errors.nrrd");
    const std::string render = "render " + volume.string() + " --force -o " + tmp("parse_errors.png").string() + " ";
    expectOneLineError(runCvc(render + "--skip-cell 0"), "--skip-cell: Value 0 not in range 1 to 64");
    expectOneLineError(runCvc(render + "--polyp-elevation 500 --display ic5"), "--polyp-elevation");
    expectOneLineError(runCvc(render + "--size"), "--size");
    expectOneLineError(runCvc(render + "--no-such-option"), "--no-such-option");
    const auto help = runCvc("render --help");
    EXPECT_EQ(help.exitCode, 0);
    EXPECT_NE(help.out.find("--display"), std::string::npos);
}

TEST(CliRender, WritesAPngOfThePhantom) {
    const fs::path volume = tmp("cli_ball.nrrd");
    ASSERT_EQ(runCvc("phantom --kind ball --size 48 --force -o " + volume.string()).exitCode, 0);
    const fs::path png = tmp("cli_ball.png");
    const auto run = runCvc("render " + volume.string() + " --iso 0 --size 64x48 --force -o " + png.string());
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const std::string bytes = readWholeFile(png);
    ASSERT_GT(bytes.size(), 24u);
    EXPECT_EQ(bytes.substr(1, 3), "PNG");
    // IHDR holds width and height big-endian at bytes 16..23.
    auto be32 = [&](std::size_t at) {
        return (static_cast<unsigned char>(bytes[at]) << 24) | (static_cast<unsigned char>(bytes[at + 1]) << 16) |
               (static_cast<unsigned char>(bytes[at + 2]) << 8) | static_cast<unsigned char>(bytes[at + 3]);
    };
    EXPECT_EQ(be32(16), 64);
    EXPECT_EQ(be32(20), 48);
}

/// --json: the summary says what the last lines say, names the files written, and an existing
/// summary is refused before any work unless --force.
TEST(CliRender, JsonSummaryOfAPinholeView) {
    const fs::path volume = tmp("cli_json_ball.nrrd");
    ASSERT_EQ(runCvc("phantom --kind ball --size 48 --force -o " + volume.string()).exitCode, 0);
    const fs::path png = tmp("cli_json_ball.png");
    const fs::path json = tmp("cli_json_ball.json");
    fs::remove(png);
    fs::remove(json);
    const std::string command = "render " + volume.string() + " --iso 0 --size 64x48 --stats -o " + png.string() +
                                " --json " + json.string();
    const auto run = runCvc(command);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json summary = nlohmann::json::parse(readWholeFile(json));
    EXPECT_EQ(summary.at("view"), "pinhole");
    EXPECT_EQ(summary.at("width"), 64);
    EXPECT_EQ(summary.at("height"), 48);
    EXPECT_EQ(summary.at("png"), fs::absolute(png).string());
    EXPECT_TRUE(fs::exists(summary.at("png").get<std::string>()));
    EXPECT_NE(run.out.find(" on " + summary.at("renderer").get<std::string>() + ": "), std::string::npos) << run.out;
    EXPECT_GT(summary.at("seconds").get<double>(), 0.0);
    EXPECT_GT(summary.at("fetches_per_ray").at("mean").get<double>(), 0.0);
    EXPECT_GE(summary.at("fetches_per_ray").at("max").get<double>(), summary.at("fetches_per_ray").at("mean").get<double>());

    // An existing summary is refused before any work, naming it, unless --force: no PNG is written.
    fs::remove(png);
    const auto refused = runCvc(command);
    EXPECT_NE(refused.exitCode, 0);
    EXPECT_EQ(lineCount(refused.err), 1) << refused.err;
    EXPECT_NE(refused.err.find(json.string()), std::string::npos) << refused.err;
    EXPECT_FALSE(fs::exists(png));
    const auto forced = runCvc(command + " --force");
    ASSERT_EQ(forced.exitCode, 0) << forced.err;
    EXPECT_TRUE(fs::exists(png));
    EXPECT_EQ(nlohmann::json::parse(readWholeFile(json)).at("png"), fs::absolute(png).string());
}

}  // namespace
