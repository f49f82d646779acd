// `cvc render --dicom-out`: every picture of a display render (both eyes' walls and the sheet)
// goes back as a DICOM Secondary Capture that GDCM reads back with the PNG's pixels, in the
// source series' study with new, valid and unique UIDs; a pinhole view of a non-DICOM source
// gets the marked placeholders.
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "engine/output/png_reader.h"
#include "tests/support/run_program.h"
#include "volumes/dicom_secondary_capture.h"

namespace {

namespace fs = std::filesystem;
using testing_support::processTmp;
using testing_support::runCvc;

/// The DICOM file's pixels equal the PNG's (RGB of RGBA).
void expectSamePixels(const volumes::SecondaryCaptureFile& dicom, const fs::path& png) {
    const colon::RgbaImage picture = engine::readPng(png.string());
    ASSERT_EQ(dicom.width, picture.width) << png;
    ASSERT_EQ(dicom.height, picture.height) << png;
    std::size_t differing = 0;
    for (std::size_t pixel = 0, n = static_cast<std::size_t>(picture.width) * static_cast<std::size_t>(picture.height);
         pixel < n; ++pixel) {
        for (std::size_t channel = 0; channel < 3; ++channel) {
            differing += dicom.rgb[pixel * 3 + channel] != picture.rgba[pixel * 4 + channel] ? 1 : 0;
        }
    }
    EXPECT_EQ(differing, 0u) << png;
}

TEST(CvcDicomOut, EveryPictureOfADisplayRenderGoesBackInTheSourceStudy) {
    const std::string series = std::string(CVC_SHARED_DATA_DIR) + "/dicom/ibsi_sts008_ct";
    if (!fs::exists(series)) GTEST_SKIP() << series << " not found";
    const fs::path out = processTmp("dicom_render"), dicom = processTmp("dicom_render_dcm");
    fs::remove_all(out);
    fs::remove_all(dicom);
    // One pose inside the thigh scan's air, looking along its axis.
    const auto run = runCvc("render " + series + " --display ic5 --position 68,60,20 --look-at 68,60,120 --up 0,-1,0 "
                            "--scale 4 -o " + out.string() + " --dicom-out " + dicom.string());
    ASSERT_EQ(run.exitCode, 0) << run.err;

    const volumes::DicomIdentifiers source = volumes::dicomIdentifiersOf(series);
    std::set<std::string> instances;
    std::map<std::string, std::set<std::string>> seriesByDescription;
    int files = 0;
    for (const char* eye : {"left", "right"}) {
        for (const char* wall : {"front", "back", "left", "right", "floor"}) {
            const fs::path file = dicom / (std::string("frame_0000_") + eye + "_" + wall + ".dcm");
            const volumes::SecondaryCaptureFile read = volumes::readSecondaryCapture(file.string());
            expectSamePixels(read, out / "frame_0000" / eye / (std::string(wall) + ".png"));
            EXPECT_EQ(read.sopClassUid, "1.2.840.10008.5.1.4.1.1.7");
            EXPECT_EQ(read.patientId, source.patientId);
            EXPECT_EQ(read.patientName, source.patientName);
            EXPECT_EQ(read.studyInstanceUid, source.studyInstanceUid);
            EXPECT_EQ(read.seriesDescription, std::string("cvc ic5 frame_0000 ") + eye + " eye");
            EXPECT_TRUE(volumes::isValidDicomUid(read.sopInstanceUid)) << read.sopInstanceUid;
            EXPECT_TRUE(volumes::isValidDicomUid(read.seriesInstanceUid)) << read.seriesInstanceUid;
            EXPECT_NE(read.seriesInstanceUid, source.sourceSeriesUid);
            instances.insert(read.sopInstanceUid);
            seriesByDescription[read.seriesDescription].insert(read.seriesInstanceUid);
            ++files;
        }
    }
    const volumes::SecondaryCaptureFile sheet = volumes::readSecondaryCapture((dicom / "frame_0000_sheet.dcm").string());
    expectSamePixels(sheet, out / "frame_0000" / "sheet.png");
    instances.insert(sheet.sopInstanceUid);
    seriesByDescription[sheet.seriesDescription].insert(sheet.seriesInstanceUid);
    ++files;

    EXPECT_EQ(instances.size(), static_cast<std::size_t>(files));  // every instance UID unique
    ASSERT_EQ(seriesByDescription.size(), 3u);                   // left eye, right eye, sheet
    std::set<std::string> seriesUids;
    for (const auto& [description, uids] : seriesByDescription) {
        EXPECT_EQ(uids.size(), 1u) << description;  // one series per eye: its walls share it
        seriesUids.insert(*uids.begin());
    }
    EXPECT_EQ(seriesUids.size(), 3u);
    if (fs::exists("/usr/bin/gdcminfo")) {  // GDCM's own tool reads them too (libgdcm-tools)
        for (const auto& entry : fs::directory_iterator(dicom)) {
            const std::string command = "/usr/bin/gdcminfo '" + entry.path().string() + "' >/dev/null 2>&1";
            EXPECT_EQ(std::system(command.c_str()), 0) << entry.path();
        }
    }

    // Nothing is replaced without --force.
    const auto again = runCvc("render " + series + " --display ic5 --position 68,60,20 --look-at 68,60,120 --up 0,-1,0 "
                              "--scale 4 -o " + processTmp("dicom_render_again").string() + " --dicom-out " + dicom.string());
    EXPECT_NE(again.exitCode, 0);
    EXPECT_NE(again.err.find("holds DICOM files"), std::string::npos) << again.err;
}

TEST(CvcDicomOut, APinholeViewOfANonDicomSourceGetsPlaceholders) {
    const fs::path volume = processTmp("dicom_ball.nrrd"), png = processTmp("dicom_ball.png"), dicom = processTmp("dicom_ball");
    fs::remove_all(dicom);
    ASSERT_EQ(runCvc("phantom --kind ball --size 32 --force -o " + volume.string()).exitCode, 0);
    const auto run = runCvc("render " + volume.string() + " --size 64x48 --force -o " + png.string() + " --dicom-out " +
                            dicom.string());
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const volumes::SecondaryCaptureFile read = volumes::readSecondaryCapture((dicom / "render.dcm").string());
    expectSamePixels(read, png);
    EXPECT_EQ(read.patientId, volumes::kPlaceholderPatientId);
    EXPECT_EQ(read.patientName, volumes::kPlaceholderPatientName);
    EXPECT_TRUE(volumes::isValidDicomUid(read.studyInstanceUid));
}

}  // namespace
