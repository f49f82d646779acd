// The files 3D Slicer opens: Markups JSON for centrelines and unseen patches, the lumen as a
// segmentation NRRD. Checked on an analysis made here on an oblique, anisotropic grid (so the
// patient frame differs from the volume's axes in every component): positions back to volume
// millimetres by an inverse computed here, within 0.01 mm; the segmentation read back by the
// project's NRRD reader, label for label against the analysis, with each segment's header
// fields and an extent recounted here.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "colon/colon_error.h"
#include "colon/slicer_files.h"
#include "volumes/nrrd_io.h"

namespace {

namespace fs = std::filesystem;

/// A 20 x 14 x 9 grid at (0.7, 0.9, 2.5) mm, rotated 30 degrees about an oblique axis, with two
/// colon segments (boxes of label 10 and 11), some outside air (1) and a short piece of colon (9).
colon::ColonAnalysis obliqueAnalysis() {
    colon::ColonAnalysis analysis;
    volumes::Volume& labels = analysis.labels;
    labels.dims = {20, 14, 9};
    labels.spacingMm = {0.7, 0.9, 2.5};
    labels.originLps = {-120.5, 33.25, 417.0};
    labels.directionLps = glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(30.0), glm::normalize(glm::dvec3(1, 2, 3))));
    labels.hu.assign(labels.voxelCount(), colon::kLabelNone);
    for (int k = 0; k < labels.dims[2]; ++k) {
        for (int j = 0; j < labels.dims[1]; ++j) {
            for (int i = 0; i < labels.dims[0]; ++i) {
                int16_t code = colon::kLabelNone;
                if (i >= 2 && i <= 6 && j >= 3 && j <= 9 && k >= 1 && k <= 7) code = colon::kLabelFirstSegment;
                if (i >= 11 && i <= 17 && j >= 5 && j <= 12 && k >= 2 && k <= 4) code = colon::kLabelFirstSegment + 1;
                if (i == 0) code = colon::kLabelOutside;
                if (i == 9 && j == 1) code = colon::kLabelShortColon;
                labels.hu[labels.linearIndex(i, j, k)] = code;
            }
        }
    }
    analysis.segments.resize(2);
    analysis.segments[0].centreline.pointsMm = {{2.8, 5.4, 5.0}, {3.5, 5.4, 7.5}, {3.5, 6.3, 10.0}};
    analysis.segments[1].centreline.pointsMm = {{9.1, 7.2, 7.5}, {10.5, 8.1, 7.5}};
    return analysis;
}

/// Volume millimetres of a patient-frame point: the inverse of patient = origin + D (mm), with
/// D inverted here as a general matrix (not by the transpose the library may use).
glm::dvec3 volumeMmFromPatient(const volumes::Volume& volume, const glm::dvec3& lps) {
    return glm::inverse(volume.directionLps) * (lps - volume.originLps);
}

std::string readText(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

/// The `key:=value` lines of a NRRD header.
std::map<std::string, std::string> keyValuesOf(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::map<std::string, std::string> fields;
    for (std::string line; std::getline(in, line) && !line.empty();) {
        const std::size_t at = line.find(":=");
        if (at != std::string::npos) fields[line.substr(0, at)] = line.substr(at + 2);
    }
    return fields;
}

fs::path freshFolder(const std::string& name) {
    const fs::path folder = fs::path(CVC_TEST_TMP_DIR) / "slicer_files" / name;
    fs::remove_all(folder);
    fs::create_directories(folder);
    return folder;
}

TEST(SlicerFiles, CentrelineCurveHoldsTheSegmentsPointsInPatientLps) {
    const colon::ColonAnalysis analysis = obliqueAnalysis();
    for (std::size_t s = 0; s < analysis.segments.size(); ++s) {
        const nlohmann::json doc = nlohmann::json::parse(colon::centrelineMarkupsJson(analysis, s, analysis.labels));
        EXPECT_EQ(doc["@schema"], colon::kMarkupsSchemaId);
        ASSERT_EQ(doc["markups"].size(), 1u);
        const nlohmann::json& markup = doc["markups"][0];
        EXPECT_EQ(markup["type"], "Curve");
        EXPECT_EQ(markup["coordinateSystem"], "LPS");
        EXPECT_EQ(markup["coordinateUnits"], "mm");
        EXPECT_EQ(markup["name"], "colon segment " + std::to_string(s + 1));
        const auto& pointsMm = analysis.segments[s].centreline.pointsMm;
        ASSERT_EQ(markup["controlPoints"].size(), pointsMm.size());
        for (std::size_t p = 0; p < pointsMm.size(); ++p) {
            const nlohmann::json& point = markup["controlPoints"][p];
            const glm::dvec3 lps(point["position"][0], point["position"][1], point["position"][2]);
            EXPECT_LT(glm::length(volumeMmFromPatient(analysis.labels, lps) - pointsMm[p]), 0.01) << "segment " << s << " point " << p;
            EXPECT_GT(glm::length(lps - pointsMm[p]), 10.0);  // the patient frame is really another frame here
            EXPECT_EQ(point["positionStatus"], "defined");
            EXPECT_EQ(point["orientation"].size(), 9u);
        }
    }
    EXPECT_THROW(colon::centrelineMarkupsJson(analysis, 2, analysis.labels), colon::ColonError);
}

TEST(SlicerFiles, UnseenPatchesAreAFiducialListLargestFirst) {
    const colon::ColonAnalysis analysis = obliqueAnalysis();
    std::vector<colon::UnseenPatch> patches(2);
    patches[0].areaMm2 = 42.25;
    patches[0].centreMm = {4.0, 3.0, 12.5};
    patches[1].areaMm2 = 11.0;
    patches[1].centreMm = {12.0, 6.5, 5.0};
    const nlohmann::json doc = nlohmann::json::parse(colon::unseenPatchesMarkupsJson(patches, analysis.labels));
    const nlohmann::json& markup = doc["markups"][0];
    EXPECT_EQ(markup["type"], "Fiducial");
    ASSERT_EQ(markup["controlPoints"].size(), 2u);
    for (std::size_t p = 0; p < patches.size(); ++p) {
        const nlohmann::json& point = markup["controlPoints"][p];
        EXPECT_EQ(point["label"], "patch " + std::to_string(p + 1));
        const glm::dvec3 lps(point["position"][0], point["position"][1], point["position"][2]);
        EXPECT_LT(glm::length(volumeMmFromPatient(analysis.labels, lps) - patches[p].centreMm), 0.01);
    }
    EXPECT_NE(markup["controlPoints"][0]["description"].get<std::string>().find("42.2"), std::string::npos);
    // No patches: a valid, empty list.
    EXPECT_TRUE(nlohmann::json::parse(colon::unseenPatchesMarkupsJson({}, analysis.labels))["markups"][0]["controlPoints"].empty());
}

TEST(SlicerFiles, LumenSegmentationReadsBackLabelForLabelOnTheSameGrid) {
    const colon::ColonAnalysis analysis = obliqueAnalysis();
    const fs::path file = freshFolder("segmentation") / "lumen.seg.nrrd";
    colon::writeLumenSegmentation(analysis, file.string(), false);

    const volumes::Volume back = volumes::readNrrd(file.string());
    const volumes::Volume& grid = analysis.labels;
    ASSERT_EQ(back.dims, grid.dims);
    EXPECT_LT(glm::length(back.spacingMm - grid.spacingMm), 1e-9);
    EXPECT_LT(glm::length(back.originLps - grid.originLps), 1e-9);
    for (int axis = 0; axis < 3; ++axis) EXPECT_LT(glm::length(back.directionLps[axis] - grid.directionLps[axis]), 1e-9);
    // Segment N holds exactly the voxels of colon segment N; nothing else is labelled.
    std::array<std::array<int, 6>, 2> extents{};
    for (auto& e : extents) e = {1000, -1, 1000, -1, 1000, -1};
    for (int k = 0; k < grid.dims[2]; ++k) {
        for (int j = 0; j < grid.dims[1]; ++j) {
            for (int i = 0; i < grid.dims[0]; ++i) {
                const int code = grid.at(i, j, k);
                const int expected = code >= colon::kLabelFirstSegment ? code - colon::kLabelFirstSegment + 1 : 0;
                ASSERT_EQ(back.at(i, j, k), expected) << i << ',' << j << ',' << k;
                if (expected == 0) continue;
                auto& e = extents[static_cast<std::size_t>(expected - 1)];
                e = {std::min(e[0], i), std::max(e[1], i), std::min(e[2], j), std::max(e[3], j), std::min(e[4], k), std::max(e[5], k)};
            }
        }
    }
    EXPECT_EQ(extents[0], (std::array<int, 6>{2, 6, 3, 9, 1, 7}));
    const auto fields = keyValuesOf(file);
    for (int s = 0; s < 2; ++s) {
        const std::string key = "Segment" + std::to_string(s) + "_";
        EXPECT_EQ(fields.at(key + "Name"), "colon segment " + std::to_string(s + 1));
        EXPECT_EQ(fields.at(key + "LabelValue"), std::to_string(s + 1));
        const auto& e = extents[static_cast<std::size_t>(s)];
        std::ostringstream extent;
        extent << e[0] << ' ' << e[1] << ' ' << e[2] << ' ' << e[3] << ' ' << e[4] << ' ' << e[5];
        EXPECT_EQ(fields.at(key + "Extent"), extent.str());
        std::istringstream colour(fields.at(key + "Color"));
        double r = -1, g = -1, b = -1;
        colour >> r >> g >> b;
        EXPECT_TRUE(r >= 0 && r <= 1 && g >= 0 && g <= 1 && b >= 0 && b <= 1) << fields.at(key + "Color");
    }
    EXPECT_EQ(fields.count("Segment2_ID"), 0u);
    EXPECT_EQ(fields.at("Segmentation_MasterRepresentation"), "Binary labelmap");
    EXPECT_NE(readText(file).find("encoding: gzip"), std::string::npos);
}

TEST(SlicerFiles, SegmentationRefusesToReplaceAFileAndTooManySegments) {
    colon::ColonAnalysis analysis = obliqueAnalysis();
    const fs::path file = freshFolder("refusals") / "lumen.seg.nrrd";
    colon::writeLumenSegmentation(analysis, file.string(), false);
    EXPECT_THROW(colon::writeLumenSegmentation(analysis, file.string(), false), volumes::VolumeError);
    EXPECT_NO_THROW(colon::writeLumenSegmentation(analysis, file.string(), true));
    analysis.segments.resize(256);
    EXPECT_THROW(colon::writeLumenSegmentation(analysis, file.string(), true), colon::ColonError);
}

TEST(SlicerFiles, LabelNrrdRefusesAWrongCountAndHeaderBreakingPairs) {
    const colon::ColonAnalysis analysis = obliqueAnalysis();
    const fs::path folder = freshFolder("label_nrrd");
    const std::vector<std::uint8_t> tooFew(analysis.labels.voxelCount() - 1, 0);
    EXPECT_THROW(volumes::writeLabelNrrd(analysis.labels, tooFew, {}, (folder / "a.nrrd").string()), volumes::VolumeError);
    const std::vector<std::uint8_t> labels(analysis.labels.voxelCount(), 0);
    EXPECT_THROW(volumes::writeLabelNrrd(analysis.labels, labels, {{"Name", "two\nlines"}}, (folder / "b.nrrd").string()),
                 volumes::VolumeError);
    EXPECT_THROW(volumes::writeLabelNrrd(analysis.labels, labels, {{"a:=b", "c"}}, (folder / "c.nrrd").string()),
                 volumes::VolumeError);
    EXPECT_FALSE(fs::exists(folder / "b.nrrd"));
}

}  // namespace
