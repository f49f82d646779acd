// `cvc render --display`: the frame folders it writes, --resume rendering only what is
// missing, --force needed to replace, and refusals with one clear line.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/folder_compare.h"
#include "tests/support/run_program.h"

namespace {

namespace fs = std::filesystem;
using testing_support::runCvc;

fs::path tmp(const std::string& name) { return fs::path(CVC_TEST_TMP_DIR) / name; }

const char* kWalls[] = {"front", "back", "left", "right", "floor"};

/// A small tube phantom, a 3-point path along its axis (3 frames at 5 mm) and a display of
/// tiny walls, so a sequence renders in a moment.
struct SmallScene {
    SmallScene() {
        fs::create_directories(tmp("display"));
        volume = testing_support::processTmp("display_tube.nrrd");
        EXPECT_EQ(runCvc("phantom --kind tube --size 32 --force -o " + volume.string()).exitCode, 0);
        path = testing_support::processTmp("display_path.txt");
        std::ofstream(path) << "15.5 15.5 5\n15.5 15.5 10\n15.5 15.5 15\n";
        display = testing_support::processTmp("display_tiny.json");
        std::ofstream(display) << R"({"name": "tiny", "box_size_m": [2.4, 2.4, 2.4], "map": "none", "walls": [
            {"name": "front", "width": 32, "height": 24}, {"name": "back", "width": 32, "height": 24},
            {"name": "left", "width": 32, "height": 24}, {"name": "right", "width": 32, "height": 24},
            {"name": "floor", "width": 32, "height": 32}]})";
    }
    std::string command(const fs::path& out, const std::string& extra = "") const {
        return "render " + volume.string() + " --display " + display.string() + " --path " + path.string() +
               " --path-step 5 --iso -480 --scale 5 -o " + out.string() + " " + extra;
    }
    fs::path volume, path, display;
};

TEST(DisplayRender, WritesEveryWallForBothEyesAndASheetPerFrame) {
    const SmallScene scene;
    const fs::path out = tmp("display/frames_layout");
    fs::remove_all(out);
    const auto run = runCvc(scene.command(out));
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_NE(run.out.find("rendered 3 frame(s) (30 wall images)"), std::string::npos) << run.out;
    EXPECT_TRUE(fs::exists(out / "render.json"));
    for (const char* frame : {"frame_0000", "frame_0001", "frame_0002"}) {
        EXPECT_TRUE(fs::exists(out / frame / "sheet.png")) << frame;
        for (const char* eye : {"left", "right"}) {
            for (const char* wall : kWalls) EXPECT_TRUE(fs::exists(out / frame / eye / (std::string(wall) + ".png")));
        }
    }
    EXPECT_FALSE(fs::exists(out / "frame_0003"));
    // The review page beside the frames (tests/app/review_page_test.py opens it in a browser).
    for (const char* file : {"index.html", "review_data.js", "review_volume.js", "review_page.js", "review_page.css"}) {
        EXPECT_TRUE(fs::exists(out / file)) << file;
    }
    EXPECT_NE(run.out.find("review page: " + (out / "index.html").string()), std::string::npos) << run.out;
    // Progress goes to stderr, one line per frame when it is not a terminal.
    EXPECT_NE(run.err.find("frames 3/3"), std::string::npos) << run.err;
}

/// --json: the frames, wall images and files of the run, as its last lines say them; after a
/// frame is lost, --resume's summary counts the frames it kept.
TEST(DisplayRender, JsonSummaryCountsTheFramesRenderedAndKept) {
    const SmallScene scene;
    const fs::path out = tmp("display/frames_json");
    const fs::path json = tmp("display/frames_json.json");
    fs::remove_all(out);
    fs::remove(json);
    const auto run = runCvc(scene.command(out, "--json " + json.string()));
    ASSERT_EQ(run.exitCode, 0) << run.err;
    nlohmann::json summary = nlohmann::json::parse(testing_support::readWholeFile(json));
    EXPECT_EQ(summary.at("view"), "display");
    EXPECT_EQ(summary.at("display"), "tiny");
    EXPECT_EQ(summary.at("ranks"), 1);
    EXPECT_EQ(summary.at("frames_total"), 3);
    EXPECT_EQ(summary.at("frames_rendered"), 3);
    EXPECT_EQ(summary.at("frames_kept"), 0);
    EXPECT_EQ(summary.at("wall_images"), 30);
    EXPECT_NE(run.out.find("rendered 3 frame(s) (30 wall images)"), std::string::npos) << run.out;
    EXPECT_EQ(summary.at("folder"), fs::absolute(out).string());
    EXPECT_TRUE(fs::exists(summary.at("review_page").get<std::string>()));
    EXPECT_GT(summary.at("ray_casting_ms_per_stereo_frame").get<double>(), 0.0);

    fs::remove_all(out / "frame_0001");
    fs::remove(json);  // an existing summary needs --force, which would replace the frames too
    const auto resumed = runCvc(scene.command(out, "--resume --json " + json.string()));
    ASSERT_EQ(resumed.exitCode, 0) << resumed.err;
    summary = nlohmann::json::parse(testing_support::readWholeFile(json));
    EXPECT_EQ(summary.at("frames_rendered"), 1);
    EXPECT_EQ(summary.at("frames_kept"), 2);
    EXPECT_EQ(summary.at("wall_images"), 10);
}

TEST(DisplayRender, ResumeRendersOnlyWhatIsMissingAndForceIsNeededToReplace) {
    const SmallScene scene;
    const fs::path out = tmp("display/frames_resume");
    fs::remove_all(out);
    ASSERT_EQ(runCvc(scene.command(out)).exitCode, 0);
    const auto keptTime = fs::last_write_time(out / "frame_0000" / "sheet.png");

    // Without --resume or --force the folder is left alone.
    const auto refused = runCvc(scene.command(out));
    EXPECT_NE(refused.exitCode, 0);
    EXPECT_EQ(testing_support::lineCount(refused.err), 1) << refused.err;
    EXPECT_NE(refused.err.find("pass --resume to continue it or --force to replace it"), std::string::npos);
    EXPECT_EQ(fs::last_write_time(out / "frame_0000" / "sheet.png"), keptTime);

    // A frame lost (or never finished): --resume renders that one alone.
    fs::remove_all(out / "frame_0001");
    fs::create_directories(out / ".frame_0001.partial" / "left");  // what an interrupted run leaves
    const auto resumed = runCvc(scene.command(out, "--resume"));
    ASSERT_EQ(resumed.exitCode, 0) << resumed.err;
    EXPECT_NE(resumed.out.find("rendered 1 frame(s)"), std::string::npos) << resumed.out;
    EXPECT_NE(resumed.out.find("kept 2 finished frame(s)"), std::string::npos) << resumed.out;
    EXPECT_TRUE(fs::exists(out / "frame_0001" / "right" / "floor.png"));
    EXPECT_FALSE(fs::exists(out / ".frame_0001.partial"));
    EXPECT_EQ(fs::last_write_time(out / "frame_0000" / "sheet.png"), keptTime);
    // The page rewritten at the end lists the kept frames and the new one.
    const std::string pageData = testing_support::readWholeFile(out / "review_data.js");
    for (const char* frame : {"frame_0000/sheet.png", "frame_0001/sheet.png", "frame_0002/sheet.png"}) {
        EXPECT_NE(pageData.find(frame), std::string::npos) << frame;
    }

    // Resuming with other settings would mix two renders: refused.
    const auto changed = runCvc(scene.command(out, "--resume --light-distance 10"));
    EXPECT_NE(changed.exitCode, 0);
    EXPECT_NE(changed.err.find("other inputs or settings"), std::string::npos) << changed.err;

    // --force replaces our output (a page file half written by an interrupted run included) and
    // leaves the user's own files alone.
    std::ofstream(out / "notes.txt") << "mine";
    std::ofstream(out / ".index.html.partial") << "<html";
    const auto forced = runCvc(scene.command(out, "--force"));
    ASSERT_EQ(forced.exitCode, 0) << forced.err;
    EXPECT_NE(forced.out.find("rendered 3 frame(s)"), std::string::npos) << forced.out;
    EXPECT_TRUE(fs::exists(out / "notes.txt"));
    EXPECT_FALSE(fs::exists(out / ".index.html.partial"));
    EXPECT_TRUE(fs::exists(out / "index.html"));
}

/// Runs `script` with sh in a mount namespace of its own, where it may mount a small tmpfs that
/// nothing else sees and that vanishes with it; returns sh's exit code, or -1 where this machine
/// allows no such namespace (neither as root nor through a user namespace).
int runInPrivateMount(const std::string& script) {
    for (const char* unshare : {"unshare --mount", "unshare --user --map-root-user --mount"}) {
        if (std::system((std::string(unshare) + " true >/dev/null 2>&1").c_str()) != 0) continue;
        const std::string command = std::string(unshare) + " sh -c '" + script + "'";
        const int status = std::system(command.c_str());
        return WIFEXITED(status) ? WEXITSTATUS(status) : 255;
    }
    return -1;
}

/// A disk that fills up mid-run: one message naming the file and why, the finished frames kept,
/// no half-written one, and --resume (with room again) completing the folder as a clean run writes it.
TEST(DisplayRender, AFullDiskStopsWithOneMessageAndResumeCompletesTheFolder) {
    const SmallScene scene;
    const fs::path clean = tmp("display/frames_full_disk_clean");
    fs::remove_all(clean);
    ASSERT_EQ(runCvc(scene.command(clean)).exitCode, 0);
    // Room for the manifest and one and a half frames, in tmpfs pages.
    const auto pages = [](std::uintmax_t bytes) { return (bytes + 4095) / 4096; };
    std::uintmax_t framePages = 0;
    for (const auto& entry : fs::recursive_directory_iterator(clean / "frame_0000")) {
        if (entry.is_regular_file()) framePages += pages(entry.file_size());
    }
    const std::uintmax_t roomKiB = 4 * (pages(fs::file_size(clean / "render.json")) + framePages * 3 / 2);

    const fs::path mount = tmp("display/full_disk_mount");
    const fs::path kept = tmp("display/frames_full_disk");
    fs::remove_all(kept);
    fs::create_directories(mount);
    const fs::path err = tmp("display/full_disk.err");
    const std::string full = (mount / "frames").string();
    const int code = runInPrivateMount("mount -t tmpfs -o size=" + std::to_string(roomKiB) + "k cvc_full " +
                                       mount.string() + " && \"" CVC_BINARY "\" " + scene.command(full) + " 2>" +
                                       err.string() + " </dev/null >/dev/null; code=$?; cp -a " + full + " " +
                                       kept.string() + "; exit $code");
    if (code == -1) GTEST_SKIP() << "no private mount namespace here (unshare)";
    const std::string message = testing_support::readWholeFile(err);
    EXPECT_NE(code, 0) << message;
    // The progress bar shares stderr; the error is its one last line.
    const std::string last = message.substr(message.rfind("cvc: error: "));
    EXPECT_EQ(testing_support::lineCount(last), 1) << message;
    EXPECT_NE(last.find("No space left on device"), std::string::npos) << message;
    EXPECT_NE(last.find(full), std::string::npos) << message;
    ASSERT_TRUE(fs::exists(kept / "frame_0000" / "sheet.png")) << message;
    EXPECT_FALSE(fs::exists(kept / "frame_0002"));
    for (const auto& entry : fs::directory_iterator(kept)) {
        EXPECT_EQ(entry.path().filename().string().rfind(".frame_", 0), std::string::npos) << "left " << entry.path();
    }

    const auto resumed = runCvc(scene.command(kept, "--resume"));
    ASSERT_EQ(resumed.exitCode, 0) << resumed.err;
    EXPECT_NE(resumed.out.find("kept 1 finished frame(s)"), std::string::npos) << resumed.out;
    testing_support::expectSameFolders(clean, kept);
}

/// Ctrl-C in the middle of a fly-through: exit status 130 with one line that says the finished
/// frames are kept, no half-written frame left behind, and --resume completing the folder as a
/// clean run writes it.
TEST(DisplayRender, CtrlCKeepsTheFinishedFramesAndResumeCompletesTheFolder) {
    const SmallScene scene;
    // A path of 60 frames 0.5 mm apart, long enough that the signal comes while frames remain.
    const fs::path longPath = testing_support::processTmp("display_long_path.txt");
    {
        std::ofstream path(longPath);
        for (int i = 0; i <= 60; ++i) path << "15.5 15.5 " << 2.0 + 0.45 * i << '\n';
    }
    const auto command = [&](const fs::path& out, const std::string& extra) {
        return "render " + scene.volume.string() + " --display " + scene.display.string() + " --path " +
               longPath.string() + " --path-step 0.5 --iso -480 --scale 5 -o " + out.string() + " " + extra;
    };
    const fs::path clean = tmp("display/frames_interrupt_clean");
    fs::remove_all(clean);
    ASSERT_EQ(runCvc(command(clean, "")).exitCode, 0);

    const fs::path out = tmp("display/frames_interrupt");
    fs::remove_all(out);
    const fs::path err = tmp("display/interrupt.err");
    // Job control on (set -m): a background job of a script would otherwise start with SIGINT
    // ignored. The signal goes once the second frame is in place.
    const std::string script = "set -m; \"" CVC_BINARY "\" " + command(out, "") + " </dev/null >/dev/null 2>" +
                               err.string() + " & pid=$!; for i in $(seq 6000); do [ -e " +
                               (out / "frame_0001").string() + " ] && break; sleep 0.01; done; kill -INT $pid; wait $pid";
    const int status = std::system(("bash -c '" + script + "'").c_str());
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    const std::string message = testing_support::readWholeFile(err);
    ASSERT_EQ(code, 130) << message;
    const std::string last = message.substr(message.rfind("cvc: "));
    EXPECT_EQ(testing_support::lineCount(last), 1) << message;
    EXPECT_NE(last.find("interrupted; the finished frames are kept (continue with --resume)"), std::string::npos)
        << message;
    ASSERT_TRUE(fs::exists(out / "frame_0001" / "sheet.png"));
    EXPECT_FALSE(fs::exists(out / "frame_0060")) << "the run was not interrupted";
    for (const auto& entry : fs::directory_iterator(out)) {
        EXPECT_EQ(entry.path().filename().string().rfind(".frame_", 0), std::string::npos) << "left " << entry.path();
    }

    const auto resumed = runCvc(command(out, "--resume"));
    ASSERT_EQ(resumed.exitCode, 0) << resumed.err;
    EXPECT_NE(resumed.out.find("kept "), std::string::npos) << resumed.out;
    testing_support::expectSameFolders(clean, out);
}

TEST(DisplayRender, ConformalDisplayWritesTheBeforeAfterSheet) {
    const SmallScene scene;
    const fs::path display = tmp("display/tiny_ic.json");
    std::ofstream(display) << R"({"name": "tiny-ic", "box_size_m": [2.95, 2.21, 2.95], "map": "conformal", "walls": [
        {"name": "front", "width": 40, "height": 30}, {"name": "back", "width": 40, "height": 30},
        {"name": "left", "width": 40, "height": 30}, {"name": "right", "width": 40, "height": 30},
        {"name": "floor", "width": 30, "height": 30}]})";
    const fs::path out = tmp("display/frames_conformal");
    fs::remove_all(out);
    const auto run = runCvc("render " + scene.volume.string() + " --display " + display.string() +
                                " --position 15.5,15.5,8 --look-at 15.5,15.5,20 --up 0,1,0 --map-size 32 --before-after "
                                "--force -o " + out.string(),
                            "CVC_CACHE_DIR=" + tmp("display/cache").string());
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_TRUE(fs::exists(out / "frame_0000" / "before_after.png"));
    EXPECT_TRUE(fs::exists(out / "frame_0000" / "left" / "front.png"));
    EXPECT_NE(run.err.find("map: conformal, 32^2 per face"), std::string::npos) << run.err;
}

TEST(DisplayRender, FourWallCaveRendersThroughItsMapAndRefusesTheCabinsBake) {
    // The classic CAVE (no ceiling, no back) at cave4's box, small walls: every wall for both
    // eyes through its conformal map; the cabin's bake is not its map.
    const SmallScene scene;
    const fs::path display = tmp("display/tiny_cave4.json");
    std::ofstream(display) << R"({"name": "tiny-cave4", "box_size_m": [2.4, 2.4, 2.4], "map": "conformal", "walls": [
        {"name": "front", "width": 32, "height": 32}, {"name": "left", "width": 32, "height": 32},
        {"name": "right", "width": 32, "height": 32}, {"name": "floor", "width": 32, "height": 32}]})";
    const std::string cache = "CVC_CACHE_DIR=" + tmp("display/cache").string();
    const fs::path out = tmp("display/frames_cave4");
    fs::remove_all(out);
    const std::string render = "render " + scene.volume.string() + " --display " + display.string() +
                               " --position 15.5,15.5,8 --look-at 15.5,15.5,20 --up 0,1,0 --force -o " + out.string();
    const auto run = runCvc(render + " --map-size 32", cache);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_NE(run.err.find("map: conformal, 32^2 per face"), std::string::npos) << run.err;
    for (const char* eye : {"left", "right"}) {
        for (const char* wall : {"front", "left", "right", "floor"}) {
            EXPECT_TRUE(fs::exists(out / "frame_0000" / eye / (std::string(wall) + ".png"))) << eye << " " << wall;
        }
        EXPECT_FALSE(fs::exists(out / "frame_0000" / eye / "back.png"));
    }
    const fs::path cabinMap = tmp("display/cabin_for_cave4.cvcm");
    ASSERT_EQ(runCvc("bake --box 2.4 2.4 2.4 --size 16 --mesh-resolution 16 --force -o " + cabinMap.string(), cache).exitCode, 0);
    const fs::path cave4Map = tmp("display/cave4.cvcm");
    const auto bake = runCvc("bake --display " + display.string() + " --size 16 --mesh-resolution 16 --force -o " +
                             cave4Map.string(), cache);
    ASSERT_EQ(bake.exitCode, 0) << bake.err;
    EXPECT_NE(bake.out.find("lacking ceiling, back"), std::string::npos) << bake.out;
    const auto wrong = runCvc(render + " --cube-map " + cabinMap.string(), cache);
    EXPECT_NE(wrong.exitCode, 0);
    EXPECT_NE(wrong.err.find("was baked for a display lacking ceiling, the display 'tiny-cave4' lacks ceiling, back"),
              std::string::npos)
        << wrong.err;
    const auto right = runCvc(render + " --cube-map " + cave4Map.string(), cache);
    EXPECT_EQ(right.exitCode, 0) << right.err;
    // The linear baseline bends cave4's rays too.
    const auto linear = runCvc(render + " --map linear --map-size 16", cache);
    EXPECT_EQ(linear.exitCode, 0) << linear.err;
    EXPECT_NE(linear.err.find("map: linear, 16^2 per face"), std::string::npos) << linear.err;
}

TEST(DisplayRender, BakedCubeMapOfTheDisplayIsUsedAndRecorded) {
    const SmallScene scene;
    // A display of its own with the map centred below the box centre: `cvc bake --display`
    // takes box, centre and map from it, and `cvc render --cube-map` accepts the result.
    const fs::path display = tmp("display/tiny_lowered.json");
    std::ofstream(display) << R"({"name": "tiny-lowered", "box_size_m": [2.95, 2.21, 2.95], "map": "linear",
        "map_centre_m": [0, -0.2, 0], "walls": [
        {"name": "front", "width": 40, "height": 30}, {"name": "back", "width": 40, "height": 30},
        {"name": "left", "width": 40, "height": 30}, {"name": "right", "width": 40, "height": 30},
        {"name": "floor", "width": 30, "height": 30}]})";
    const std::string cache = "CVC_CACHE_DIR=" + tmp("display/cache_lowered").string();
    const fs::path cubeMap = tmp("display/tiny_lowered.cvcm");
    const auto bake = runCvc("bake --display " + display.string() + " --size 16 --force -o " + cubeMap.string(), cache);
    ASSERT_EQ(bake.exitCode, 0) << bake.err;
    EXPECT_NE(bake.out.find("map centre (0, -0.2, 0) m"), std::string::npos) << bake.out;

    const fs::path out = tmp("display/frames_cube_map");
    fs::remove_all(out);
    const auto run = runCvc("render " + scene.volume.string() + " --display " + display.string() +
                                " --position 15.5,15.5,8 --look-at 15.5,15.5,20 --up 0,1,0 --force"
                                " --cube-map " + cubeMap.string() + " -o " + out.string(),
                            cache);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    // The file's size is the one used (a --map-size beside it is refused: tests/app/cli_errors_test).
    EXPECT_NE(run.err.find("map: linear, 16^2 per face, from " + cubeMap.string()), std::string::npos) << run.err;
    EXPECT_TRUE(fs::exists(out / "frame_0000" / "left" / "front.png"));
    const std::string manifest = testing_support::readWholeFile(out / "render.json");
    EXPECT_NE(manifest.find("\"" + fs::absolute(cubeMap).string() + "\""), std::string::npos) << manifest;

    // Without the file the same display uses the cached bake, the very one `cvc bake` stored: one
    // builder of the bake request, one cache entry. No file is recorded.
    const fs::path cached = tmp("display/frames_cached_map");
    fs::remove_all(cached);
    const auto bakedHere = runCvc("render " + scene.volume.string() + " --display " + display.string() +
                                      " --position 15.5,15.5,8 --look-at 15.5,15.5,20 --up 0,1,0 --map-size 16 --force"
                                      " -o " + cached.string(),
                                  cache);
    ASSERT_EQ(bakedHere.exitCode, 0) << bakedHere.err;
    EXPECT_NE(bakedHere.err.find("map: linear, 16^2 per face, loaded from"), std::string::npos) << bakedHere.err;
    EXPECT_EQ(testing_support::readWholeFile(cached / "render.json").find(".cvcm"), std::string::npos);
}

TEST(DisplayRender, RefusesWhatItCannotDo) {
    const SmallScene scene;
    // Two opposite walls are not a disc: no map can open the rest onto them.
    const auto pairFile = tmp("display/pair.json");
    std::filesystem::create_directories(pairFile.parent_path());
    std::ofstream(pairFile) << R"({"name": "pair", "map": "conformal", "walls": [)"
                               R"({"name": "left", "width": 32, "height": 32}, {"name": "right", "width": 32, "height": 32}]})";
    const auto pair = runCvc("render " + scene.volume.string() + " --display " + pairFile.string() +
                             " --position 15,15,8 --look-at 15,15,20 --up 0,1,0 -o " + tmp("display/pair").string());
    EXPECT_NE(pair.exitCode, 0);
    EXPECT_EQ(testing_support::lineCount(pair.err), 1) << pair.err;
    EXPECT_NE(pair.err.find("are in pieces"), std::string::npos) << pair.err;

    const auto noPose = runCvc("render " + scene.volume.string() + " --display cave6 -o " + tmp("display/nopose").string());
    EXPECT_NE(noPose.exitCode, 0);
    EXPECT_NE(noPose.err.find("needs --path, or --position and --look-at"), std::string::npos) << noPose.err;

    const auto badDisplay = runCvc("render " + scene.volume.string() + " --display no-such-display --path " +
                                   scene.path.string() + " -o " + tmp("display/bad").string());
    EXPECT_NE(badDisplay.exitCode, 0);
    EXPECT_NE(badDisplay.err.find("neither a preset"), std::string::npos) << badDisplay.err;
}

}  // namespace
