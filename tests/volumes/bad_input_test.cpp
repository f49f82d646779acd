/// Bad input: truncated files, headers that disagree with the data, unsupported pixel types,
/// NaN/Inf, absurd spacing, empty or broken DICOM folders. Each must end in one VolumeError
/// that names the file and the problem (and, through `cvc info`, a non-zero exit), never a crash.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>

#include <gdcmAttribute.h>
#include <gdcmReader.h>
#include <gdcmWriter.h>
#include <gtest/gtest.h>

#include "tests/support/run_program.h"
#include "tests/volumes/test_support.h"
#include "volumes/dicom_reader.h"
#include "volumes/load_volume.h"
#include "volumes/nifti_reader.h"
#include "volumes/nrrd_io.h"
#include "volumes/raw_reader.h"

namespace volumes {
namespace {

using testing::bytesOf;
using testing::scratchFolder;
using testing::writeBytes;

/// Expects loadVolume(path) to throw a VolumeError whose message names `path` and contains `problem`.
void expectLoadError(const std::string& path, const std::string& problem, const LoadOptions& options = {}) {
    try {
        loadVolume(path, options);
        ADD_FAILURE() << path << ": loaded without error, expected '" << problem << "'";
    } catch (const VolumeError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find(problem), std::string::npos) << "message: " << message;
        EXPECT_NE(message.find(std::filesystem::path(path).filename().string()), std::string::npos)
            << "message does not name the file: " << message;
    }
}

std::string nrrdText(const std::string& type, const std::string& sizes, const std::string& extra = "") {
    return "NRRD0004\ntype: " + type + "\ndimension: 3\nsizes: " + sizes +
           "\nspace: left-posterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,2)\nendian: little\n"
           "encoding: raw\n" +
           extra + "\n";
}

std::string floats(std::vector<float> values) {
    return {reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float)};
}

TEST(BadInput, NrrdTruncatedAndOversized) {
    const std::string folder = scratchFolder("bad_nrrd");
    const std::vector<int16_t> voxels(4 * 4 * 4, 7);
    writeBytes(folder + "/short.nrrd", nrrdText("short", "4 4 4") + bytesOf(voxels).substr(0, 100));
    expectLoadError(folder + "/short.nrrd", "truncated");
    writeBytes(folder + "/long.nrrd", nrrdText("short", "4 4 4") + bytesOf(voxels) + "extra");
    expectLoadError(folder + "/long.nrrd", "the header's sizes and type call for 128");
    const std::string gz = testing::deflateBytes(bytesOf(voxels), true);
    std::string header = nrrdText("short", "4 4 4");
    header.replace(header.find("encoding: raw"), 13, "encoding: gzip");
    writeBytes(folder + "/cut.nrrd", header + gz.substr(0, gz.size() / 2));
    expectLoadError(folder + "/cut.nrrd", "truncated");
    writeBytes(folder + "/garbage.nrrd", header + std::string(64, 'x'));
    expectLoadError(folder + "/garbage.nrrd", "corrupt");
    writeBytes(folder + "/noheader.nrrd", "NRRD0004\ntype: short\n");
    expectLoadError(folder + "/noheader.nrrd", "header");
    writeBytes(folder + "/detached.nhdr", nrrdText("short", "4 4 4", "data file: missing.raw"));
    expectLoadError(folder + "/detached.nhdr", "missing.raw");
}

TEST(BadInput, NrrdUnsupportedTypesAndShapes) {
    const std::string folder = scratchFolder("bad_nrrd_types");
    writeBytes(folder + "/int64.nrrd", nrrdText("int64", "2 2 2") + std::string(64, '\0'));
    expectLoadError(folder + "/int64.nrrd", "unsupported NRRD type 'int64'");
    std::string fourD = nrrdText("short", "2 2 2");
    fourD.replace(fourD.find("dimension: 3"), 12, "dimension: 4");
    writeBytes(folder + "/4d.nrrd", fourD);
    expectLoadError(folder + "/4d.nrrd", "dimension is 4");
    writeBytes(folder + "/huge.nrrd", nrrdText("short", "4096 4096 4096"));
    expectLoadError(folder + "/huge.nrrd", "exceed the limit");
    writeBytes(folder + "/negative.nrrd", nrrdText("short", "-4 4 4"));
    expectLoadError(folder + "/negative.nrrd", "outside 1..4096");
    writeBytes(folder + "/text.nrrd", nrrdText("short", "2 2 2", "encoding: text") + "1 2 3");
    expectLoadError(folder + "/text.nrrd", "unsupported encoding 'text'");
    writeBytes(folder + "/notnrrd.nrrd", "P6\n2 2\n255\n");
    expectLoadError(folder + "/notnrrd.nrrd", "not a NRRD file");
}

TEST(BadInput, NanAndInfInFloatData) {
    const std::string folder = scratchFolder("bad_float");
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    writeBytes(folder + "/nan.nrrd", nrrdText("float", "2 1 1") + floats({0.0f, nan}));
    expectLoadError(folder + "/nan.nrrd", "voxel 1 is not a finite number");
    writeBytes(folder + "/big.nrrd", nrrdText("float", "2 1 1") + floats({1e6f, 0.0f}));
    expectLoadError(folder + "/big.nrrd", "outside the int16 range");
    writeBytes(folder + "/inf.mha",
               "NDims = 3\nDimSize = 2 1 1\nElementType = MET_FLOAT\nElementDataFile = LOCAL\n" + floats({inf, 0.0f}));
    expectLoadError(folder + "/inf.mha", "voxel 0 is not a finite number");
    writeBytes(folder + "/nan.raw", floats({0.0f, 0.0f, nan, 0.0f}));
    LoadOptions raw;
    raw.raw = parseRawSpec("2x2x1:float:1x1x1");
    expectLoadError(folder + "/nan.raw", "voxel 2 is not a finite number", raw);
}

TEST(BadInput, AbsurdSpacing) {
    const std::string folder = scratchFolder("bad_spacing");
    std::string zero = nrrdText("short", "2 2 2");
    zero.replace(zero.find("(0,0,2)"), 7, "(0,0,0)");
    writeBytes(folder + "/zero.nrrd", zero + std::string(16, '\0'));
    expectLoadError(folder + "/zero.nrrd", "voxel spacing along axis 2 is 0 mm");
    std::string huge = nrrdText("short", "2 2 2");
    huge.replace(huge.find("(1,0,0)"), 7, "(1e9,0,0)");
    writeBytes(folder + "/huge.nrrd", huge + std::string(16, '\0'));
    expectLoadError(folder + "/huge.nrrd", "voxel spacing along axis 0 is 1e+09 mm");
    writeBytes(folder + "/nan.mha",
               "NDims = 3\nDimSize = 2 2 2\nElementSpacing = 1 nan 1\nElementType = MET_SHORT\n"
               "ElementDataFile = LOCAL\n" +
                   std::string(16, '\0'));
    expectLoadError(folder + "/nan.mha", "ElementSpacing");
    EXPECT_THROW(parseRawSpec("2x2x2:int16:1x1x500"), VolumeError);
}

TEST(BadInput, MetaImageHeaderDisagreesWithData) {
    const std::string folder = scratchFolder("bad_mha");
    const std::string header = "NDims = 3\nDimSize = 4 4 4\nElementType = MET_SHORT\nElementDataFile = LOCAL\n";
    writeBytes(folder + "/short.mha", header + std::string(100, '\0'));
    expectLoadError(folder + "/short.mha", "truncated");
    writeBytes(folder + "/type.mha",
               "NDims = 3\nDimSize = 4 4 4\nElementType = MET_LONG_LONG\nElementDataFile = LOCAL\n");
    expectLoadError(folder + "/type.mha", "ElementType = 'MET_LONG_LONG' is not supported");
    writeBytes(folder + "/rgb.mha",
               "NDims = 3\nDimSize = 1 1 1\nElementNumberOfChannels = 3\nElementType = MET_UCHAR\n"
               "ElementDataFile = LOCAL\nabc");
    expectLoadError(folder + "/rgb.mha", "ElementNumberOfChannels");
    writeBytes(folder + "/nodata.mha", "NDims = 3\nDimSize = 4 4 4\nElementType = MET_SHORT\n");
    expectLoadError(folder + "/nodata.mha", "ElementDataFile");
    writeBytes(folder + "/list.mhd", "NDims = 3\nDimSize = 4 4 4\nElementType = MET_SHORT\nElementDataFile = LIST\n");
    expectLoadError(folder + "/list.mhd", "several files");
}

TEST(BadInput, RawSizeDisagreesWithDescription) {
    const std::string folder = scratchFolder("bad_raw");
    writeBytes(folder + "/v.raw", std::string(1000, '\0'));
    LoadOptions options;
    options.raw = parseRawSpec("10x10x10:int16:1x1x1");
    expectLoadError(folder + "/v.raw",
                    "file holds 1000 bytes, the raw description (10x10x10 int16, skip 0) calls for 2000", options);
}

/// A NIfTI-1 single file written field by field (offsets from nifti1.h), independent of niftilib.
std::string niftiBytes(std::array<short, 3> dims, short datatype, short bitpix, float slope, float inter,
                       const std::string& data) {
    std::string h(352, '\0');
    auto put = [&](std::size_t offset, const auto& value) { std::memcpy(h.data() + offset, &value, sizeof(value)); };
    put(0, int32_t{348});
    const short dim[8] = {3, dims[0], dims[1], dims[2], 1, 1, 1, 1};
    std::memcpy(h.data() + 40, dim, sizeof(dim));
    put(70, datatype);
    put(72, bitpix);
    const float pixdim[8] = {1, 2, 2, 2, 1, 1, 1, 1};
    std::memcpy(h.data() + 76, pixdim, sizeof(pixdim));
    put(108, 352.0f);
    put(112, slope);
    put(116, inter);
    put(123, char{10});  // xyzt_units: mm
    put(254, short{1});  // sform_code: scanner
    const float srow[3][4] = {{-2, 0, 0, 10}, {0, -2, 0, 20}, {0, 0, 2, 30}};
    std::memcpy(h.data() + 280, srow, sizeof(srow));
    std::memcpy(h.data() + 344, "n+1\0", 4);
    return h + data;
}

TEST(NiftiReader, AppliesSformAndScaling) {
    const std::string folder = scratchFolder("nifti_scaled");
    const std::vector<int16_t> stored = {0, 1, 2, 3, 4, 5, 6, 7};
    writeBytes(folder + "/v.nii", niftiBytes({2, 2, 2}, 4, 16, 2.0f, -1000.0f, bytesOf(stored)));
    const Volume v = readNifti(folder + "/v.nii");
    EXPECT_EQ(v.hu, (std::vector<int16_t>{-1000, -998, -996, -994, -992, -990, -988, -986}));
    EXPECT_NEAR(v.spacingMm.x, 2.0, 1e-9);
    // RAS sform (-2, -2, 2) becomes LPS (+x, +y, +z); origin (10, 20, 30) RAS is (-10, -20, 30) LPS.
    EXPECT_NEAR(v.directionLps[0].x, 1.0, 1e-9);
    EXPECT_NEAR(v.directionLps[1].y, 1.0, 1e-9);
    EXPECT_NEAR(v.originLps.x, -10.0, 1e-6);
    EXPECT_NEAR(v.originLps.y, -20.0, 1e-6);
    EXPECT_NEAR(v.originLps.z, 30.0, 1e-6);
}

TEST(NiftiReader, ReadsHeaderAndImagePair) {
    // NIfTI-1 as two files: magic "ni1", data from byte 0 of the .img.
    const std::string folder = scratchFolder("nifti_pair");
    const std::vector<int16_t> stored = {10, 20, 30, 40, 50, 60, 70, 80};
    std::string header = niftiBytes({2, 2, 2}, 4, 16, 0.0f, 0.0f, "").substr(0, 348);
    std::memcpy(header.data() + 344, "ni1\0", 4);
    const float zero = 0.0f;
    std::memcpy(header.data() + 108, &zero, 4);
    writeBytes(folder + "/v.hdr", header);
    writeBytes(folder + "/v.img", bytesOf(stored));
    EXPECT_EQ(loadVolume(folder + "/v.hdr").hu, stored);
}

TEST(BadInput, NiftiProblems) {
    const std::string folder = scratchFolder("bad_nifti");
    writeBytes(folder + "/complex.nii", niftiBytes({2, 2, 2}, 32, 64, 0.0f, 0.0f, std::string(64, '\0')));
    expectLoadError(folder + "/complex.nii", "is not supported");
    writeBytes(folder + "/short.nii", niftiBytes({4, 4, 4}, 4, 16, 0.0f, 0.0f, std::string(20, '\0')));
    expectLoadError(folder + "/short.nii", "truncated");
    writeBytes(folder + "/nan.nii", niftiBytes({2, 1, 1}, 16, 32, 0.0f, 0.0f, floats({1.0f, std::nanf("")})));
    expectLoadError(folder + "/nan.nii", "not a finite number");
    writeBytes(folder + "/garbage.nii", std::string(400, 'g'));
    expectLoadError(folder + "/garbage.nii", "niftilib cannot read it");
}

/// Copies the sarcoma series into a scratch folder, letting `edit` change each slice's data set.
std::string editedSeries(const std::string& name, const std::function<bool(int index, gdcm::DataSet&)>& edit) {
    const std::string folder = scratchFolder(name);
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(testing::sharedData("dicom/ibsi_sts008_ct")))
        files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (std::size_t n = 0; n < files.size(); ++n) {
        gdcm::Reader reader;
        reader.SetFileName(files[n].c_str());
        EXPECT_TRUE(reader.Read());
        if (!edit(static_cast<int>(n), reader.GetFile().GetDataSet())) continue;  // false: leave the slice out
        gdcm::Writer writer;
        writer.SetFile(reader.GetFile());
        const std::string out = (std::filesystem::path(folder) / files[n].filename()).string();
        writer.SetFileName(out.c_str());
        EXPECT_TRUE(writer.Write());
    }
    return folder;
}

TEST(BadInput, DicomFolders) {
    const std::string empty = scratchFolder("dicom_empty");
    expectLoadError(empty, "is empty");
    const std::string notDicom = scratchFolder("dicom_none");
    writeBytes(notDicom + "/readme.txt", "no images here");
    expectLoadError(notDicom, "no DICOM image");
}

TEST(BadInput, OptionsForAnotherKindOfInputAreRefused) {
    // A raw description given with a DICOM folder, or a series UID with a single file, would be
    // silently unused: both are refused, naming the path.
    const std::string folder = scratchFolder("dicom_with_raw");
    LoadOptions raw;
    raw.raw = parseRawSpec("4x4x4:int16:1x1x1");
    expectLoadError(folder, "a raw description is for a headerless file, this is a folder", raw);
    const std::string file = scratchFolder("series_uid_file") + "/ball.nrrd";
    writeBytes(file, nrrdText("short", "2 2 2") + std::string(16, '\0'));
    LoadOptions series;
    series.dicomSeriesUid = "1.2.3";
    expectLoadError(file, "a DICOM series UID picks a series in a folder, this is a file", series);
    EXPECT_NO_THROW(loadVolume(file));  // the same file without the option loads
}

TEST(BadInput, DicomMissingSliceIsUnevenSpacing) {
    const std::string folder = editedSeries("dicom_gap", [](int n, gdcm::DataSet&) { return n != 20; });
    expectLoadError(folder, "uneven slice spacing");
}

TEST(BadInput, DicomGantryTiltIsRefused) {
    // Shift each slice along y by tan(15 degrees) times its distance from the first.
    const std::string folder = editedSeries("dicom_tilt", [](int, gdcm::DataSet& ds) {
        gdcm::Attribute<0x0020, 0x0032> position;
        position.Set(ds);
        const double z = position.GetValue(2);
        position.SetValue(position.GetValue(1) + std::tan(15.0 * 3.14159265358979 / 180.0) * (z + 272.95), 1);
        ds.Replace(position.GetAsDataElement());
        return true;
    });
    expectLoadError(folder, "gantry tilt of about 15");
}

TEST(BadInput, DicomDuplicatePositions) {
    const std::string folder = editedSeries("dicom_duplicate", [](int, gdcm::DataSet&) { return true; });
    std::filesystem::copy_file(std::filesystem::path(folder) / "000010.dcm",
                               std::filesystem::path(folder) / "copy.dcm");
    expectLoadError(folder, "same position");
}

TEST(BadInput, DicomTruncatedSlice) {
    const std::string folder = editedSeries("dicom_truncated", [](int, gdcm::DataSet&) { return true; });
    const auto victim = std::filesystem::path(folder) / "000030.dcm";
    std::filesystem::resize_file(victim, std::filesystem::file_size(victim) / 2);
    try {
        readDicomSeries(folder);
        ADD_FAILURE() << "a truncated slice loaded without error";
    } catch (const VolumeError& e) {
        EXPECT_NE(std::string(e.what()).find("000030.dcm"), std::string::npos) << e.what();
    }
}

TEST(CvcInfo, PrintsTheSharedAbdomen) {
    const auto run = testing_support::runCvc("info '" + testing::sharedData("ct/ts_example_abdomen_3mm.nii.gz") + "'");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    for (const char* expected : {"NIfTI", "122 x 101 x 112", "3 x 3 x 3 mm", "RAS", "-1207 .. 3382", "histogram", "air",
                                 "soft tissue", "bricks:"}) {
        EXPECT_NE(run.out.find(expected), std::string::npos) << expected << " missing from:\n" << run.out;
    }
}

TEST(CvcInfo, NamesTheSeriesItReadFromAFolderOfTwo) {
    const std::string folder = scratchFolder("info_two_series");
    for (const char* name : {"ibsi_ct_phantom_chest", "ibsi_sts008_ct"}) {
        std::filesystem::copy(testing::sharedData(std::string("dicom/") + name), std::filesystem::path(folder) / name);
    }
    const auto largest = testing_support::runCvc("info '" + folder + "'");
    ASSERT_EQ(largest.exitCode, 0) << largest.err;
    EXPECT_NE(largest.out.find("2 series in the folder"), std::string::npos) << largest.out;
    EXPECT_NE(largest.out.find("204 x 201 x 60"), std::string::npos) << largest.out;  // the chest: 60 files
    const std::string sarcomaUid = listDicomSeries(testing::sharedData("dicom/ibsi_sts008_ct")).front().seriesUid;
    const auto chosen = testing_support::runCvc("info '" + folder + "' --series " + sarcomaUid);
    ASSERT_EQ(chosen.exitCode, 0) << chosen.err;
    EXPECT_NE(chosen.out.find("141 x 137 x 51"), std::string::npos) << chosen.out;
    const auto missing = testing_support::runCvc("info '" + folder + "' --series 1.2.3");
    EXPECT_NE(missing.exitCode, 0);
    EXPECT_NE(missing.err.find("no series with SeriesInstanceUID 1.2.3"), std::string::npos) << missing.err;
}

TEST(CvcInfo, FailsWithOneLineOnBadInput) {
    const std::string folder = scratchFolder("info_bad");
    writeBytes(folder + "/short.nrrd", nrrdText("short", "4 4 4") + std::string(10, '\0'));
    for (const std::string& arguments :
         {"info '" + folder + "/short.nrrd'", "info '" + folder + "'", "info '" + folder + "/missing.nii'",
          "info '" + folder + "/short.nrrd' --raw 1x1"}) {
        const auto run = testing_support::runCvc(arguments);
        EXPECT_NE(run.exitCode, 0) << arguments;
        EXPECT_EQ(testing_support::lineCount(run.err), 1) << arguments << ":\n" << run.err;
        EXPECT_NE(run.err.find("error"), std::string::npos) << run.err;
    }
}

}  // namespace
}  // namespace volumes
