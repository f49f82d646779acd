// The cube map of a display: one builder of the bake request (box, map centre and map from the
// display), the refusal of displays without a map, and a baked file checked against the display
// it is used for: another box, centre or kind is refused by name; the right file gives the same
// texels, and the same pixels, as the cached bake.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "conformal/cube_map_baker.h"
#include "engine/display/display_json.h"
#include "engine/display/display_map.h"
#include "engine/render/raycaster.h"
#include "engine/render/volume_texture.h"
#include "tests/support/gpu_test_fixture.h"
#include "volumes/analytic_phantom.h"
#include "volumes/brick_minmax.h"

namespace {

namespace fs = std::filesystem;

fs::path tmp(const std::string& name) { return fs::path(CVC_TEST_TMP_DIR) / "display_map" / name; }

/// Points $CVC_CACHE_DIR at an empty folder of the test's own for the test's lifetime, so the
/// user's cache is neither read nor filled and tests run in parallel do not share entries.
class PrivateCache {
public:
    explicit PrivateCache(const std::string& name) : mDirectory(tmp("cache_" + name)) {
        fs::remove_all(mDirectory);
        fs::create_directories(mDirectory);
        setenv("CVC_CACHE_DIR", mDirectory.c_str(), 1);
    }
    ~PrivateCache() { unsetenv("CVC_CACHE_DIR"); }
    PrivateCache(const PrivateCache&) = delete;
    PrivateCache& operator=(const PrivateCache&) = delete;

private:
    fs::path mDirectory;
};

/// The message of the std::invalid_argument that `attempt` throws ("" and a failure if none).
template <typename Attempt>
std::string invalidArgumentMessage(const Attempt& attempt) {
    try {
        attempt();
    } catch (const std::invalid_argument& error) {
        return error.what();
    }
    ADD_FAILURE() << "no std::invalid_argument";
    return "";
}

/// The ic5 display with the linear map: its bakes take milliseconds, where the conformal map's
/// Ricci flow takes seconds, and the checks of a file do not depend on the kind.
engine::Display linearIc5() {
    engine::Display display = engine::displayPreset("ic5");
    display.map = conformal::MapKind::Linear;
    return display;
}

/// Bakes `settings` without the cache (as `cvc bake --no-cache` would) into a file.
fs::path bakeFile(const std::string& name, const conformal::BakeSettings& settings) {
    fs::create_directories(tmp(""));
    const fs::path path = tmp(name);
    conformal::saveCubeMap(conformal::bakeCubeMap(settings), path);
    return path;
}

TEST(BakeSettingsFor, Ic5BakesTheImmersiveCabinAboutItsCentre) {
    const conformal::BakeSettings settings = engine::bakeSettingsFor(engine::loadDisplay("ic5"), 64);
    EXPECT_EQ(settings.size, 64);
    EXPECT_EQ(settings.box.size, conformal::immersiveCabinBox().size);
    EXPECT_EQ(settings.box.mapCentre, conformal::immersiveCabinBox().mapCentre);
    EXPECT_EQ(settings.kind, conformal::MapKind::Conformal);
    // The mesh and flow are not the display's business: they keep the bake's defaults.
    EXPECT_EQ(settings.mesh.resolution, conformal::SphereMeshSettings{}.resolution);
}

TEST(BakeSettingsFor, DisplayFileGivesItsBoxMapCentreAndMap) {
    fs::create_directories(tmp(""));
    const fs::path file = tmp("offset_centre.json");
    std::ofstream(file) << R"({"name": "lab", "box_size_m": [3, 2.5, 2.8], "map": "linear",
        "map_centre_m": [0.1, -0.2, 0.05], "walls": [
        {"name": "front", "width": 64, "height": 48}, {"name": "back", "width": 64, "height": 48},
        {"name": "left", "width": 64, "height": 48}, {"name": "right", "width": 64, "height": 48},
        {"name": "floor", "width": 64, "height": 64}]})";
    const engine::Display display = engine::loadDisplay(file.string());
    EXPECT_EQ(display.mapCentreM, glm::dvec3(0.1, -0.2, 0.05));
    const conformal::BakeSettings settings = engine::bakeSettingsFor(display, 32);
    EXPECT_EQ(settings.box.size, glm::dvec3(3.0, 2.5, 2.8));
    EXPECT_EQ(settings.box.mapCentre, glm::dvec3(0.1, -0.2, 0.05));
    EXPECT_EQ(settings.kind, conformal::MapKind::Linear);

    // The centre survives the display's own JSON (written into every render's manifest).
    const fs::path rewritten = tmp("offset_centre_rewritten.json");
    std::ofstream(rewritten) << engine::displayJson(display);
    EXPECT_EQ(engine::loadDisplay(rewritten.string()).mapCentreM, display.mapCentreM);
}

TEST(BakeSettingsFor, DisplayFileWithoutMapCentreCentresTheMapInTheBox) {
    fs::create_directories(tmp(""));
    const fs::path file = tmp("no_centre.json");
    std::ofstream(file) << R"({"name": "plain", "box_size_m": [3, 2.5, 2.8], "walls": [
        {"name": "front"}, {"name": "back"}, {"name": "left"}, {"name": "right"}, {"name": "floor"}]})";
    EXPECT_EQ(engine::bakeSettingsFor(engine::loadDisplay(file.string()), 32).box.mapCentre, glm::dvec3(0.0));
}

TEST(BakeSettingsFor, MapCentreOutsideTheBoxOrMalformedIsRefusedByName) {
    fs::create_directories(tmp(""));
    const fs::path outside = tmp("centre_outside.json");
    std::ofstream(outside) << R"({"name": "off", "box_size_m": [3, 2.5, 2.8], "map_centre_m": [0, 1.25, 0],
        "walls": [{"name": "front"}, {"name": "back"}, {"name": "left"}, {"name": "right"}, {"name": "floor"}]})";
    try {
        engine::loadDisplay(outside.string());
        ADD_FAILURE() << "a map centre on the ceiling's plane was accepted";
    } catch (const std::runtime_error& error) {
        EXPECT_NE(std::string(error.what()).find("map_centre_m"), std::string::npos) << error.what();
        EXPECT_NE(std::string(error.what()).find("strictly inside the box"), std::string::npos) << error.what();
    }
    const fs::path malformed = tmp("centre_malformed.json");
    std::ofstream(malformed) << R"({"name": "off", "map_centre_m": [0, 1], "walls": [{"name": "front"}]})";
    try {
        engine::loadDisplay(malformed.string());
        ADD_FAILURE() << "a map centre of two numbers was accepted";
    } catch (const std::runtime_error& error) {
        EXPECT_NE(std::string(error.what()).find("\"map_centre_m\" must be three numbers"), std::string::npos)
            << error.what();
    }
    engine::Display notFinite = engine::displayPreset("ic5");
    notFinite.mapCentreM.x = std::nan("");
    EXPECT_NE(invalidArgumentMessage([&] { engine::validateDisplay(notFinite); }).find("map_centre_m"),
              std::string::npos);
}

TEST(BakeSettingsFor, DisplaysWithoutAMapAreRefused) {
    EXPECT_EQ(invalidArgumentMessage([] { engine::bakeSettingsFor(engine::displayPreset("cave6"), 64); }),
              "display 'cave6' has no missing wall: there is no map to bake");
    // Even if asked for a map, six walls leave nothing to move the ceiling's view onto.
    engine::Display cave6Bent = engine::displayPreset("cave6");
    cave6Bent.map = conformal::MapKind::Conformal;
    EXPECT_NE(invalidArgumentMessage([&] { engine::bakeSettingsFor(cave6Bent, 64); }).find("no missing wall"),
              std::string::npos);
    engine::Display unbent = engine::displayPreset("ic5");
    unbent.map = conformal::MapKind::None;
    EXPECT_EQ(invalidArgumentMessage([&] { engine::bakeSettingsFor(unbent, 64); }),
              "display 'ic5' asks for no map (map none): there is no map to bake");
}

TEST(CubeMapFor, FileForAnotherBoxIsRefusedNamingBothBoxes) {
    conformal::BakeSettings cube = engine::bakeSettingsFor(linearIc5(), 16);
    cube.box.size = glm::dvec3(2.4);
    const fs::path file = bakeFile("cube_box.cvcm", cube);
    EXPECT_EQ(invalidArgumentMessage([&] { engine::cubeMapFor(linearIc5(), 16, file.string(), nullptr); }),
              "cube map " + file.string() +
                  " was baked for box 2.4 x 2.4 x 2.4 m, the display 'ic5' has 2.95 x 2.21 x 2.95 m");
    // The tolerance is for rounding, not for another CAVE: a millimetre is a mismatch.
    cube.box.size = conformal::immersiveCabinBox().size + glm::dvec3(0.0, 0.001, 0.0);
    const fs::path nearly = bakeFile("nearly_box.cvcm", cube);
    EXPECT_NE(invalidArgumentMessage([&] { engine::cubeMapFor(linearIc5(), 16, nearly.string(), nullptr); })
                  .find("box 2.95 x 2.211 x 2.95 m"),
              std::string::npos);
}

TEST(CubeMapFor, FileForAnotherCentreIsRefusedNamingBothCentres) {
    conformal::BakeSettings lowered = engine::bakeSettingsFor(linearIc5(), 16);
    lowered.box.mapCentre = {0.0, -0.3, 0.0};
    const fs::path file = bakeFile("lowered_centre.cvcm", lowered);
    const std::string message =
        invalidArgumentMessage([&] { engine::cubeMapFor(linearIc5(), 16, file.string(), nullptr); });
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find("map centre (0, -0.3, 0) m"), std::string::npos) << message;
    EXPECT_NE(message.find("the display 'ic5' has its map centre at (0, 0, 0) m"), std::string::npos) << message;

    // And the other way round: a display centred off the box centre refuses the centred bake.
    const fs::path centred = bakeFile("centred.cvcm", engine::bakeSettingsFor(linearIc5(), 16));
    engine::Display display = linearIc5();
    display.mapCentreM = {0.0, -0.3, 0.0};
    EXPECT_NE(invalidArgumentMessage([&] { engine::cubeMapFor(display, 16, centred.string(), nullptr); })
                  .find("centre"),
              std::string::npos);
}

TEST(CubeMapFor, FileOfAnotherKindIsRefusedNamingBothKinds) {
    const fs::path file = bakeFile("linear_ic5.cvcm", engine::bakeSettingsFor(linearIc5(), 16));
    // ic5 asks for the conformal map; checking the kind first means no Ricci flow is run here.
    EXPECT_EQ(invalidArgumentMessage(
                  [&] { engine::cubeMapFor(engine::displayPreset("ic5"), 16, file.string(), nullptr); }),
              "cube map " + file.string() + " holds the linear map, the display 'ic5' asks for conformal");
}

TEST(CubeMapFor, DisplayWithoutAMapRefusesAFile) {
    const fs::path file = bakeFile("for_cave6.cvcm", engine::bakeSettingsFor(linearIc5(), 16));
    const std::string message = invalidArgumentMessage(
        [&] { engine::cubeMapFor(engine::displayPreset("cave6"), 16, file.string(), nullptr); });
    EXPECT_EQ(message, "cube map " + file.string() +
                           " cannot be used: display 'cave6' has no missing wall: there is no map to bake");
}

TEST(CubeMapFor, RightFileGivesTheCachedBakesTexelsAtTheFilesSize) {
    const PrivateCache cache("right_file");
    const fs::path file = bakeFile("right_ic5.cvcm", engine::bakeSettingsFor(linearIc5(), 24));
    conformal::BakeReport report;
    report.wasLoadedFromCache = true;  // to see that a file load resets it
    // 48 asked for, 24 in the file: the file wins.
    const conformal::CubeMap fromFile = engine::cubeMapFor(linearIc5(), 48, file.string(), &report);
    EXPECT_FALSE(report.wasLoadedFromCache);
    EXPECT_TRUE(report.cachePath.empty());
    EXPECT_EQ(fromFile.size, 24);

    conformal::BakeReport cacheReport;
    const conformal::CubeMap fromCache = engine::cubeMapFor(linearIc5(), 24, "", &cacheReport);
    EXPECT_FALSE(cacheReport.wasLoadedFromCache);  // an empty cache: baked now, and stored
    EXPECT_TRUE(fs::exists(cacheReport.cachePath));
    EXPECT_EQ(fromCache.size, 24);
    EXPECT_EQ(fromFile.kind, fromCache.kind);
    EXPECT_EQ(fromFile.inputHash, fromCache.inputHash);
    EXPECT_EQ(fromFile.rgba, fromCache.rgba);
}

/// The pixels of one wall bent through the file's map and through the cached bake.
class CubeMapForRendering : public testing_support::GpuTest {};

TEST_F(CubeMapForRendering, RightFileRendersTheSamePixelsAsTheCachedBake) {
    const PrivateCache cache("pixels");
    // The product's map, conformal, at a small size: the Ricci flow runs twice (file and cache).
    engine::Display display = engine::displayPreset("ic5");
    for (auto& wall : display.walls) wall.width = wall.height = 40;
    const fs::path file = bakeFile("conformal_ic5.cvcm", engine::bakeSettingsFor(display, 32));
    const conformal::CubeMap fromFile = engine::cubeMapFor(display, 32, file.string(), nullptr);
    const conformal::CubeMap fromCache = engine::cubeMapFor(display, 32, "", nullptr);

    // A ball seen from inside, offset so the front wall shows its curved side bent by the map.
    volumes::BallSpec ball;
    ball.grid.dims = {48, 48, 48};
    ball.centreMm = glm::dvec3(23.5, 20.0, 26.0);
    ball.radiusMm = 18.0;
    ball.insideHu = -1000;
    ball.outsideHu = 40;
    const volumes::Volume volume = volumes::makeBallPhantom(ball);
    const volumes::BrickMinMax bricks = volumes::buildBrickMinMax(volume);
    engine::VolumeTexture texture(context(), volume);
    engine::Raycaster raycaster(context(), volume, texture, bricks);
    engine::ScenePose pose;
    pose.positionMm = glm::dvec3(23.5);
    pose.forward = {0.0, 0.0, 1.0};
    pose.up = {0.0, 1.0, 0.0};
    pose.mmPerMetre = 4.0;
    engine::RenderSettings settings;
    settings.isoHu = -480.0;
    const auto view = engine::wallView(display, engine::WallName::Front, engine::Eye::Left, pose,
                                       engine::WarpMode::Chord);
    ASSERT_EQ(view.warp.mode, engine::WarpMode::Chord);

    raycaster.setCubeMap(fromFile.size, fromFile.rgba);
    const engine::RenderedImage withFile = raycaster.render(view.rays, settings, view.warp);
    raycaster.setCubeMap(fromCache.size, fromCache.rgba);
    const engine::RenderedImage withCache = raycaster.render(view.rays, settings, view.warp);
    ASSERT_EQ(withFile.rgba.size(), withCache.rgba.size());
    EXPECT_EQ(withFile.rgba, withCache.rgba);

    // The comparison can tell maps apart: the linear baseline bends the same wall differently.
    engine::Display linear = display;
    linear.map = conformal::MapKind::Linear;
    const conformal::CubeMap linearMap = engine::cubeMapFor(linear, 32, "", nullptr);
    raycaster.setCubeMap(linearMap.size, linearMap.rgba);
    EXPECT_NE(raycaster.render(view.rays, settings, view.warp).rgba, withFile.rgba);
}

}  // namespace
