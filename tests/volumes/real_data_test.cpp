/// Every loader on the real CT in ../shared/data: sizes, spacing, orientation and HU ranges
/// as the data READMEs state them, and the same voxels whichever format they come from.
#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include <gtest/gtest.h>

#include "tests/volumes/test_support.h"
#include "volumes/dicom_reader.h"
#include "volumes/load_volume.h"
#include "volumes/nifti_reader.h"
#include "volumes/nrrd_io.h"

namespace volumes {
namespace {

using testing::expectSameVolume;
using testing::sharedData;

struct Expected {
    const char* file;
    std::array<int, 3> dims;
    glm::dvec3 spacingMm;
    int16_t minHu, maxHu;
    glm::dvec3 axisSigns;  ///< the diagonal of directionLps (all four are axis-aligned)
};

// From ../shared/data/ct/README.md.
const Expected kNrrdFiles[] = {
    {"ct/ts_example_abdomen_3mm.nrrd", {122, 101, 112}, {3.0, 3.0, 3.0}, -1207, 3382, {-1, -1, 1}},
    {"ct/invesalius_cranium_head.nrrd", {256, 256, 108}, {0.957031, 0.957031, 1.5}, -1024, 2986, {1, 1, 1}},
    {"ct/ibsi_ct_phantom_chest.nrrd", {204, 201, 60}, {0.977, 0.977, 3.0}, -1000, 3065, {1, 1, 1}},
    {"ct/ibsi_sts008_ct.nrrd", {141, 137, 51}, {0.976562, 0.976562, 3.27}, -1000, 1479, {1, 1, 1}},
};

void expectMatches(const Volume& volume, const Expected& expected) {
    EXPECT_EQ(volume.dims, expected.dims);
    for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(volume.spacingMm[axis], expected.spacingMm[axis], 1e-5);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_NEAR(volume.directionLps[i][j], i == j ? expected.axisSigns[i] : 0.0, 1e-9);
    const auto [lo, hi] = std::minmax_element(volume.hu.begin(), volume.hu.end());
    EXPECT_EQ(*lo, expected.minHu);
    EXPECT_EQ(*hi, expected.maxHu);
}

TEST(NrrdReader, ReadsEverySharedVolume) {
    for (const Expected& expected : kNrrdFiles) {
        SCOPED_TRACE(expected.file);
        const Volume volume = loadVolume(sharedData(expected.file));
        expectMatches(volume, expected);
    }
}

TEST(NrrdReader, AbdomenHasAirInsideTheBody) {
    // The abdomen scan is chosen for its air-filled colon: besides the air around the body,
    // a large share of voxels must be air (below -900 HU) and some soft tissue (0..100 HU).
    const Volume volume = loadVolume(sharedData("ct/ts_example_abdomen_3mm.nrrd"));
    const auto air = std::count_if(volume.hu.begin(), volume.hu.end(), [](int16_t v) { return v < -900; });
    const auto tissue = std::count_if(volume.hu.begin(), volume.hu.end(), [](int16_t v) { return v > 0 && v < 100; });
    EXPECT_GT(air, static_cast<long>(volume.hu.size() / 10));
    EXPECT_GT(tissue, static_cast<long>(volume.hu.size() / 10));
    // The centre of the body is not air.
    EXPECT_GT(volume.at(61, 50, 56), -500);
}

TEST(NiftiReader, AbdomenEqualsTheNrrdAfterRasToLps) {
    const Volume nifti = readNifti(sharedData("ct/ts_example_abdomen_3mm.nii.gz"));
    const Volume nrrd = readNrrd(sharedData("ct/ts_example_abdomen_3mm.nrrd"));
    expectSameVolume(nifti, nrrd, 1e-4);
    expectMatches(nifti, kNrrdFiles[0]);
}

TEST(DicomReader, ChestSeriesEqualsItsNrrd) {
    const Volume dicom = loadVolume(sharedData("dicom/ibsi_ct_phantom_chest"));
    const Volume nrrd = readNrrd(sharedData("ct/ibsi_ct_phantom_chest.nrrd"));
    expectSameVolume(dicom, nrrd, 1e-4);
    expectMatches(dicom, kNrrdFiles[2]);
}

TEST(DicomReader, SarcomaSeriesEqualsItsNrrd) {
    const Volume dicom = readDicomSeries(sharedData("dicom/ibsi_sts008_ct"));
    const Volume nrrd = readNrrd(sharedData("ct/ibsi_sts008_ct.nrrd"));
    expectSameVolume(dicom, nrrd, 1e-4);
    expectMatches(dicom, kNrrdFiles[3]);
}

TEST(DicomReader, OrdersSlicesByPositionNotFileName) {
    // Copy the series under names that reverse and shuffle the order: the volume must not change.
    const std::string folder = testing::scratchFolder("dicom_renamed");
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(sharedData("dicom/ibsi_sts008_ct")))
        files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (std::size_t n = 0; n < files.size(); ++n) {
        const std::size_t scrambled = (n * 7 + 5) % files.size();
        std::filesystem::copy_file(files[n], std::filesystem::path(folder) / ("IM" + std::to_string(1000 - scrambled)));
    }
    expectSameVolume(readDicomSeries(folder), readNrrd(sharedData("ct/ibsi_sts008_ct.nrrd")), 1e-4);
}

TEST(DicomReader, ListsOneSeriesPerSharedFolder) {
    const auto series = listDicomSeries(sharedData("dicom/ibsi_ct_phantom_chest"));
    ASSERT_EQ(series.size(), 1u);
    EXPECT_EQ(series[0].fileCount, 60u);
}

/// Compressed copies of a shared series, made with GDCM's own gdcmconv at test time.
class CompressedDicom : public ::testing::TestWithParam<std::pair<const char*, const char*>> {};

TEST_P(CompressedDicom, DecodesToTheSameVoxels) {
    const auto [name, flags] = GetParam();
    const std::string folder = testing::scratchFolder(std::string("dicom_") + name);
    const std::string source = sharedData("dicom/ibsi_sts008_ct");
    for (const auto& entry : std::filesystem::directory_iterator(source)) {
        const std::string out = (std::filesystem::path(folder) / entry.path().filename()).string();
        const std::string command = std::string("gdcmconv ") + flags + " '" + entry.path().string() + "' '" + out + "'";
        ASSERT_EQ(std::system(command.c_str()), 0) << command;
    }
    // The copies really are compressed: the transfer syntax UID changed.
    const std::string someFile = (std::filesystem::path(folder) / "000000.dcm").string();
    const std::string bytes = testing::readBytes(someFile);
    EXPECT_EQ(bytes.find("1.2.840.10008.1.2\0", 0, 18), std::string::npos) << "still implicit little endian";
    expectSameVolume(readDicomSeries(folder), readNrrd(sharedData("ct/ibsi_sts008_ct.nrrd")), 1e-4);
}

INSTANTIATE_TEST_SUITE_P(TransferSyntaxes, CompressedDicom,
                         ::testing::Values(std::make_pair("jpeg2000", "--j2k"),
                                           std::make_pair("jpeg_lossless", "--jpeg"), std::make_pair("rle", "--rle"),
                                           std::make_pair("jpegls", "--jpegls"), std::make_pair("deflated", "--deflated"),
                                           std::make_pair("explicit_little_endian", "--explicit")),
                         [](const auto& param) { return std::string(param.param.first); });

}  // namespace
}  // namespace volumes
