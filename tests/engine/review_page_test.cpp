// The review page's data: the reduced, windowed CT and its slice orientation for scans of every
// orientation, base64, the files written (escaped, ASCII, replaced whole), and the page of a
// sequence naming the images as renderSequence writes them. The page itself runs in a browser in
// tests/app/review_page_test.py.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/review/review_page.h"
#include "engine/review/review_volume.h"
#include "engine/sequence/sequence_review_page.h"

namespace {

namespace fs = std::filesystem;
using engine::ReviewPage;

fs::path tmp(const std::string& name) { return fs::path(CVC_TEST_TMP_DIR) / "review_page" / name; }

std::string readText(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

/// The JSON that a "window.NAME = ...;" script assigns.
nlohmann::json assigned(const std::string& script, const std::string& name) {
    const std::string prefix = "window." + name + " = ";
    EXPECT_EQ(script.rfind(prefix, 0), 0u) << script.substr(0, 80);
    const std::size_t end = script.rfind(';');
    return nlohmann::json::parse(script.substr(prefix.size(), end - prefix.size()));
}

volumes::Volume filledVolume(std::array<int, 3> dims, glm::dvec3 spacing, int16_t hu) {
    volumes::Volume volume;
    volume.dims = dims;
    volume.spacingMm = spacing;
    volume.hu.assign(volume.voxelCount(), hu);
    return volume;
}

TEST(ReviewVolume, WindowMapsColonWindowEdgesToBlackAndWhite) {
    EXPECT_EQ(engine::reviewGrey(-1000.0), 0);  // air in the lumen
    EXPECT_EQ(engine::reviewGrey(-950.0), 0);
    EXPECT_EQ(engine::reviewGrey(-200.0), 128);
    EXPECT_EQ(engine::reviewGrey(550.0), 255);
    EXPECT_EQ(engine::reviewGrey(1500.0), 255);
    EXPECT_GT(engine::reviewGrey(40.0), engine::reviewGrey(-100.0));  // wall brighter than fat
}

TEST(ReviewVolume, Base64MatchesTheRfcVectors) {
    const auto of = [](const std::string& text) { return engine::base64Of({text.begin(), text.end()}); };
    EXPECT_EQ(of(""), "");
    EXPECT_EQ(of("f"), "Zg==");
    EXPECT_EQ(of("fo"), "Zm8=");
    EXPECT_EQ(of("foo"), "Zm9v");
    EXPECT_EQ(of("foob"), "Zm9vYg==");
    EXPECT_EQ(of("fooba"), "Zm9vYmE=");
    EXPECT_EQ(of("foobar"), "Zm9vYmFy");
    EXPECT_EQ(engine::base64Of({0xff, 0xfe, 0x00}), "//4A");
}

TEST(ReviewVolume, BoxFilterReducesEachAxisToTheLimitAndAveragesBeforeWindowing) {
    // 330 x 100 x 9 at 0.5 x 1 x 2 mm: x by 3 (to 110), y and z kept.
    volumes::Volume volume = filledVolume({330, 100, 9}, {0.5, 1.0, 2.0}, 0);
    for (int k = 0; k < 9; ++k) {
        for (int j = 0; j < 100; ++j) {
            for (int i = 0; i < 330; ++i) {
                // Blocks of three along x: air, air, +850 HU average -383.3 HU; the last column of
                // the grid is air too.
                volume.hu[volume.linearIndex(i, j, k)] = static_cast<int16_t>(i % 3 == 2 ? 850 : -1000);
            }
        }
    }
    const engine::ReviewVolume reduced = engine::reviewVolumeOf(volume, 110);
    EXPECT_EQ(reduced.dims, (std::array<int, 3>{110, 100, 9}));
    EXPECT_EQ(reduced.factor, (std::array<int, 3>{3, 1, 1}));
    EXPECT_DOUBLE_EQ(reduced.spacingMm.x, 1.5);
    EXPECT_DOUBLE_EQ(reduced.spacingMm.z, 2.0);
    EXPECT_DOUBLE_EQ(reduced.offsetMm.x, 0.5);  // the middle voxel of the first block
    EXPECT_DOUBLE_EQ(reduced.offsetMm.y, 0.0);
    ASSERT_EQ(reduced.grey.size(), 110u * 100u * 9u);
    const uint8_t expected = engine::reviewGrey((-1000.0 - 1000.0 + 850.0) / 3.0);
    EXPECT_EQ(reduced.grey.front(), expected);
    EXPECT_EQ(reduced.grey.back(), expected);
    // Windowing each voxel first would have averaged 0, 0 and 255 to 85 instead.
    EXPECT_NE(expected, 85);

    // A side that does not divide: 161 voxels by 2 gives 81, the last block of one voxel.
    const engine::ReviewVolume odd = engine::reviewVolumeOf(filledVolume({161, 20, 20}, {1, 1, 1}, -200), 160);
    EXPECT_EQ(odd.dims, (std::array<int, 3>{81, 20, 20}));
    EXPECT_EQ(odd.grey.back(), 128);
    EXPECT_THROW(engine::reviewVolumeOf(volumes::Volume{}), std::invalid_argument);
}

TEST(ReviewVolume, SlicesFollowTheRadiologicalConventionForAnAxialLpsScan) {
    // Grid axes along L, P, S (DICOM's usual axial series).
    bool isOblique = true;
    const auto views = engine::reviewSliceViews(glm::dmat3(1.0), &isOblique);
    EXPECT_FALSE(isOblique);
    EXPECT_EQ(views[0].name, "axial");
    EXPECT_EQ(views[0].normalAxis, 2);
    EXPECT_EQ(views[0].columnAxis, 0);  // index grows toward L: the patient's right on the image's left
    EXPECT_FALSE(views[0].isColumnFlipped);
    EXPECT_EQ(views[0].rowAxis, 1);  // index grows toward P: anterior at the top
    EXPECT_FALSE(views[0].isRowFlipped);
    EXPECT_EQ(views[0].leftLabel + views[0].rightLabel + views[0].topLabel + views[0].bottomLabel, "RLAP");
    EXPECT_EQ(views[1].name, "coronal");
    EXPECT_EQ(views[1].normalAxis, 1);
    EXPECT_EQ(views[1].rowAxis, 2);
    EXPECT_TRUE(views[1].isRowFlipped);  // superior at the top, where the index is largest
    EXPECT_EQ(views[1].leftLabel + views[1].rightLabel + views[1].topLabel + views[1].bottomLabel, "RLSI");
    EXPECT_EQ(views[2].name, "sagittal");
    EXPECT_EQ(views[2].normalAxis, 0);
    EXPECT_EQ(views[2].columnAxis, 1);
    EXPECT_FALSE(views[2].isColumnFlipped);  // anterior on the left
    EXPECT_EQ(views[2].leftLabel + views[2].rightLabel + views[2].topLabel + views[2].bottomLabel, "APSI");
}

TEST(ReviewVolume, SlicesFollowThePatientForFlippedAndPermutedGrids) {
    // A RAS-ordered grid (x toward the patient's right, y anterior, z superior).
    const auto ras = engine::reviewSliceViews(glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1)));
    EXPECT_TRUE(ras[0].isColumnFlipped);
    EXPECT_TRUE(ras[0].isRowFlipped);
    EXPECT_TRUE(ras[1].isColumnFlipped);
    EXPECT_TRUE(ras[1].isRowFlipped);

    // A sagittal series: grid x along -P (anterior), grid y along -S (inferior), grid z along L.
    const glm::dmat3 sagittal(glm::dvec3(0, -1, 0), glm::dvec3(0, 0, -1), glm::dvec3(1, 0, 0));
    const auto views = engine::reviewSliceViews(sagittal);
    EXPECT_EQ(views[0].normalAxis, 1);  // axial: across S, which grid y carries
    EXPECT_EQ(views[0].columnAxis, 2);
    EXPECT_FALSE(views[0].isColumnFlipped);
    EXPECT_EQ(views[0].rowAxis, 0);
    EXPECT_TRUE(views[0].isRowFlipped);  // grid x grows anterior; the image's rows grow posterior
    EXPECT_EQ(views[2].normalAxis, 2);  // sagittal: across L, grid z
    EXPECT_EQ(views[2].rowAxis, 1);
    EXPECT_FALSE(views[2].isRowFlipped);  // grid y grows inferior, as the image's rows do

    // 20 degrees about S: the nearest axes still, and marked oblique.
    const double a = 20.0 * std::numbers::pi / 180.0;
    bool isOblique = false;
    const auto tilted = engine::reviewSliceViews(
        glm::dmat3(glm::dvec3(std::cos(a), std::sin(a), 0), glm::dvec3(-std::sin(a), std::cos(a), 0), glm::dvec3(0, 0, 1)),
        &isOblique);
    EXPECT_TRUE(isOblique);
    EXPECT_EQ(tilted[0].columnAxis, 0);
    EXPECT_EQ(tilted[0].normalAxis, 2);
}

ReviewPage samplePage() {
    ReviewPage page;
    page.title = "quote \" backslash \\ </script> <b>bold</b> \u00e9t\u00e9";
    page.facts = {{"display", "ic5"}, {"map", "conformal"}};
    for (int i = 0; i < 3; ++i) {
        engine::ReviewFrame frame;
        frame.index = i;
        frame.pose.positionMm = {10.0, 20.0 + 3.0 * i, 30.0 + 4.0 * i};  // 5 mm apart
        frame.sheet = engine::frameFolderName(i) + "/sheet.png";
        frame.images = {{"front", engine::frameFolderName(i) + "/centre/front.png", "centre eye"}};
        page.frames.push_back(frame);
    }
    return page;
}

TEST(ReviewPage, WritesThePageItsScriptsAndTheDataAsEscapedAsciiJavaScript) {
    const fs::path folder = tmp("escaped");
    fs::remove_all(folder);
    const ReviewPage page = samplePage();
    engine::writeReviewPage(folder.string(), page);
    for (const std::string& name : engine::reviewPageFileNames()) EXPECT_TRUE(fs::is_regular_file(folder / name)) << name;
    for (const auto& entry : fs::directory_iterator(folder)) {
        EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos) << entry.path();
    }

    const std::string html = readText(folder / "index.html");
    for (const char* script : {"review_data.js", "review_volume.js", "review_page.js", "review_page.css"}) {
        EXPECT_NE(html.find(script), std::string::npos) << script;
    }
    EXPECT_EQ(html.find("http"), std::string::npos) << "the page must need no network";

    const std::string script = readText(folder / "review_data.js");
    for (char c : script) ASSERT_LT(static_cast<unsigned char>(c), 128u) << "review_data.js must be ASCII";
    const nlohmann::json data = assigned(script, "REVIEW");
    EXPECT_EQ(data["title"], page.title);
    ASSERT_EQ(data["frames"].size(), 3u);
    EXPECT_DOUBLE_EQ(data["frames"][0]["arc_mm"].get<double>(), 0.0);
    EXPECT_DOUBLE_EQ(data["frames"][2]["arc_mm"].get<double>(), 10.0);
    EXPECT_DOUBLE_EQ(data["path_length_mm"].get<double>(), 10.0);
    EXPECT_EQ(data["frames"][1]["sheet"], "frame_0001/sheet.png");
    EXPECT_EQ(data["frames"][1]["images"][0]["group"], "centre eye");
    EXPECT_EQ(data["frames"][2]["pose"]["position_mm"], nlohmann::json::array({10.0, 26.0, 38.0}));
    EXPECT_FALSE(data["frames"][0].contains("patient_lps_mm"));  // no CT given
    EXPECT_TRUE(data["coverage"].is_null());
    EXPECT_TRUE(data["measurements"].empty());
    EXPECT_EQ(readText(folder / "review_volume.js"), "window.REVIEW_VOLUME = null;\n");
}

TEST(ReviewPage, CarriesCoverageMeasurementsAndTheReducedCtAndReplacesAnEarlierPage) {
    const fs::path folder = tmp("coverage");
    fs::remove_all(folder);
    engine::writeReviewPage(folder.string(), samplePage());

    ReviewPage page = samplePage();
    volumes::Volume ct = filledVolume({40, 30, 20}, {1.0, 1.0, 2.5}, -1000);
    ct.originLps = {100.0, 200.0, 300.0};
    page.ct = &ct;
    engine::ReviewCoverage coverage;
    coverage.percent = 87.5;
    coverage.seenMm2 = 700.0;
    coverage.wallMm2 = 800.0;
    coverage.overview = "coverage/overview.png";
    coverage.cumulativePercent = {40.0, 70.0, 87.5};
    engine::ReviewPatch patch;
    patch.rank = 1;
    patch.areaMm2 = 12.5;
    patch.centreMm = {1.0, 2.0, 3.0};
    patch.nearestFrame = 2;
    patch.picture = "coverage/patch_1.png";
    coverage.patches.push_back(patch);
    page.coverage = coverage;
    page.measurements = {{"polyp 3 diameter", "9.8 mm"}};
    page.frames.resize(2);
    engine::writeReviewPage(folder.string(), page);

    const nlohmann::json data = assigned(readText(folder / "review_data.js"), "REVIEW");
    EXPECT_EQ(data["frames"].size(), 2u);
    EXPECT_EQ(data["frames"][1]["patient_lps_mm"], nlohmann::json::array({110.0, 223.0, 334.0}));
    EXPECT_DOUBLE_EQ(data["coverage"]["percent"].get<double>(), 87.5);
    EXPECT_EQ(data["coverage"]["cumulative_percent"].size(), 3u);
    EXPECT_EQ(data["coverage"]["patches"][0]["nearest_frame"], 2);
    EXPECT_EQ(data["coverage"]["patches"][0]["picture"], "coverage/patch_1.png");
    EXPECT_EQ(data["measurements"][0]["label"], "polyp 3 diameter");
    EXPECT_EQ(data["measurements"][0]["value"], "9.8 mm");

    const nlohmann::json volume = assigned(readText(folder / "review_volume.js"), "REVIEW_VOLUME");
    EXPECT_EQ(volume["dims"], nlohmann::json::array({40, 30, 20}));
    EXPECT_EQ(volume["views"].size(), 3u);
    EXPECT_EQ(volume["views"][0]["labels"]["left"], "R");
    EXPECT_EQ(volume["grey_base64"].get<std::string>().size(), (40u * 30u * 20u + 2u) / 3u * 4u);
    EXPECT_DOUBLE_EQ(volume["window"]["width_hu"].get<double>(), engine::kReviewWindowWidthHu);
}

TEST(ReviewPage, OfASequenceNamesBothEyesWallsTheSheetAndBeforeAfter) {
    engine::SequenceJob job;
    job.volumePath = "scan.nrrd";
    job.display = engine::displayPreset("ic5");
    job.isWritingBeforeAfter = true;
    job.mapSource = "baked, 1024^2 per face";
    job.poses.resize(2);
    job.poses[1].positionMm = {0.0, 0.0, 7.0};
    const ReviewPage page = engine::reviewPageOfSequence(job, nullptr);
    EXPECT_EQ(page.title, "scan.nrrd on ic5");
    ASSERT_EQ(page.frames.size(), 2u);
    const engine::ReviewFrame& frame = page.frames[1];
    EXPECT_EQ(frame.index, 1);
    EXPECT_EQ(frame.pose.positionMm.z, 7.0);
    EXPECT_EQ(frame.sheet, "frame_0001/sheet.png");
    ASSERT_EQ(frame.images.size(), 2u * 5u + 1u);
    EXPECT_EQ(frame.images[0].path, "frame_0001/left/" + engine::wallNameText(job.display.walls[0].name) + ".png");
    EXPECT_EQ(frame.images[0].group, "left eye");
    EXPECT_EQ(frame.images[5].group, "right eye");
    EXPECT_EQ(frame.images[10].path, "frame_0001/before_after.png");
    bool hasMap = false;
    for (const auto& [label, value] : page.facts) hasMap = hasMap || (label == "map" && value.find("conformal") == 0);
    EXPECT_TRUE(hasMap);

    job.display.map = conformal::MapKind::None;  // no map: no before/after sheet
    EXPECT_EQ(engine::reviewPageOfSequence(job, nullptr).frames[0].images.size(), 10u);
}

}  // namespace
