// DICOM out: a Secondary Capture read back by GDCM's own image reader has our pixels and the
// identifiers we gave it; the identifiers taken from the shared real series are the ones every
// file of that series carries; a source that is not DICOM gets marked placeholders.
#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <gdcmDirectory.h>
#include <gdcmImageReader.h>
#include <gdcmScanner.h>
#include <gdcmStringFilter.h>
#include <gtest/gtest.h>

#include "tests/volumes/test_support.h"
#include "volumes/dicom_secondary_capture.h"

namespace {

using volumes::testing::scratchFolder;
using volumes::testing::sharedData;

std::string trimmed(std::string text) {
    while (!text.empty() && (text.back() == ' ' || text.back() == '\0')) text.pop_back();
    return text;
}

/// A picture whose every byte differs from its neighbours', so a swapped channel, a dropped
/// row or a flipped image cannot pass.
std::vector<uint8_t> testPicture(int width, int height) {
    std::vector<uint8_t> rgba(static_cast<std::size_t>(width * height * 4));
    for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = static_cast<uint8_t>((i * 37 + i / 4 * 11) % 251);
    return rgba;
}

TEST(DicomSecondaryCapture, GdcmReadsBackOurPixelsAndIdentifiers) {
    const std::string folder = scratchFolder("secondary_capture");
    const int width = 7, height = 5;
    const std::vector<uint8_t> rgba = testPicture(width, height);
    volumes::SecondaryCapture capture;
    capture.identifiers.patientName = "DOE^JANE";
    capture.identifiers.patientId = "PID-42";
    capture.identifiers.studyInstanceUid = volumes::newDicomUid();
    capture.seriesInstanceUid = volumes::newDicomUid();
    capture.seriesDescription = "cvc ic5 frame_0000 left eye";
    const std::string path = folder + "/picture.dcm";
    const std::string instanceUid = volumes::writeSecondaryCapture(path, width, height, rgba, capture, false);

    gdcm::ImageReader reader;
    reader.SetFileName(path.c_str());
    ASSERT_TRUE(reader.Read());
    const gdcm::Image& image = reader.GetImage();
    ASSERT_EQ(image.GetDimension(0), 7u);
    ASSERT_EQ(image.GetDimension(1), 5u);
    EXPECT_EQ(image.GetPhotometricInterpretation(), gdcm::PhotometricInterpretation::RGB);
    std::vector<char> buffer(image.GetBufferLength());
    ASSERT_EQ(buffer.size(), static_cast<std::size_t>(width * height * 3));
    ASSERT_TRUE(image.GetBuffer(buffer.data()));
    for (std::size_t pixel = 0; pixel < static_cast<std::size_t>(width * height); ++pixel) {
        for (std::size_t channel = 0; channel < 3; ++channel) {
            ASSERT_EQ(static_cast<uint8_t>(buffer[pixel * 3 + channel]), rgba[pixel * 4 + channel]) << "pixel " << pixel;
        }
    }
    gdcm::StringFilter strings;
    strings.SetFile(reader.GetFile());
    const auto value = [&](uint16_t group, uint16_t element) { return trimmed(strings.ToString(gdcm::Tag(group, element))); };
    EXPECT_EQ(value(0x0008, 0x0016), "1.2.840.10008.5.1.4.1.1.7");  // Secondary Capture Image Storage
    EXPECT_EQ(value(0x0008, 0x0018), instanceUid);
    EXPECT_TRUE(volumes::isValidDicomUid(instanceUid));
    EXPECT_EQ(value(0x0020, 0x000e), capture.seriesInstanceUid);
    EXPECT_EQ(value(0x0020, 0x000d), capture.identifiers.studyInstanceUid);
    EXPECT_EQ(value(0x0010, 0x0010), "DOE^JANE");
    EXPECT_EQ(value(0x0010, 0x0020), "PID-42");
    EXPECT_EQ(value(0x0008, 0x103e), "cvc ic5 frame_0000 left eye");

    // Our own reader agrees, and a second picture gets another instance UID.
    const volumes::SecondaryCaptureFile file = volumes::readSecondaryCapture(path);
    EXPECT_EQ(file.sopInstanceUid, instanceUid);
    EXPECT_EQ(file.patientId, "PID-42");
    const std::string second = volumes::writeSecondaryCapture(folder + "/second.dcm", width, height, rgba, capture, false);
    EXPECT_NE(second, instanceUid);
}

TEST(DicomSecondaryCapture, RefusesAnExistingFileAndPixelsOfAnotherSize) {
    const std::string folder = scratchFolder("secondary_capture_refusals");
    const std::vector<uint8_t> rgba = testPicture(4, 4);
    volumes::SecondaryCapture capture;
    capture.identifiers.studyInstanceUid = volumes::newDicomUid();
    capture.seriesInstanceUid = volumes::newDicomUid();
    const std::string path = folder + "/picture.dcm";
    volumes::writeSecondaryCapture(path, 4, 4, rgba, capture, false);
    EXPECT_THROW(volumes::writeSecondaryCapture(path, 4, 4, rgba, capture, false), std::runtime_error);
    EXPECT_NO_THROW(volumes::writeSecondaryCapture(path, 4, 4, rgba, capture, true));
    EXPECT_THROW(volumes::writeSecondaryCapture(folder + "/other.dcm", 5, 4, rgba, capture, false), std::invalid_argument);
    EXPECT_THROW(volumes::readSecondaryCapture(folder + "/missing.dcm"), std::runtime_error);
}

TEST(DicomSecondaryCapture, IdentifiersAreThoseEveryFileOfTheSharedSeriesCarries) {
    const std::string series = sharedData("dicom/ibsi_sts008_ct");
    if (!std::filesystem::exists(series)) GTEST_SKIP() << series << " not found";
    const volumes::DicomIdentifiers ids = volumes::dicomIdentifiersOf(series);
    EXPECT_FALSE(ids.isPlaceholder);
    EXPECT_TRUE(volumes::isValidDicomUid(ids.studyInstanceUid));

    // Every file of the folder, scanned on its own, carries the same patient and study.
    gdcm::Directory directory;
    directory.Load(series, true);
    gdcm::Scanner scanner;
    const gdcm::Tag patientId(0x0010, 0x0020), studyUid(0x0020, 0x000d), seriesUid(0x0020, 0x000e);
    for (const gdcm::Tag& tag : {patientId, studyUid, seriesUid}) scanner.AddTag(tag);
    ASSERT_TRUE(scanner.Scan(directory.GetFilenames()));
    int files = 0;
    for (const std::string& file : directory.GetFilenames()) {
        ASSERT_TRUE(scanner.IsKey(file.c_str())) << file;
        EXPECT_EQ(trimmed(scanner.GetValue(file.c_str(), patientId)), ids.patientId) << file;
        EXPECT_EQ(trimmed(scanner.GetValue(file.c_str(), studyUid)), ids.studyInstanceUid) << file;
        EXPECT_EQ(trimmed(scanner.GetValue(file.c_str(), seriesUid)), ids.sourceSeriesUid) << file;
        ++files;
    }
    EXPECT_EQ(files, 51);
}

TEST(DicomSecondaryCapture, ASourceThatIsNotDicomGetsMarkedPlaceholders) {
    const volumes::DicomIdentifiers first = volumes::dicomIdentifiersOf("colon.nrrd");
    const volumes::DicomIdentifiers second = volumes::dicomIdentifiersOf("colon.nrrd");
    EXPECT_TRUE(first.isPlaceholder);
    EXPECT_EQ(first.patientId, volumes::kPlaceholderPatientId);
    EXPECT_EQ(first.patientName, volumes::kPlaceholderPatientName);
    EXPECT_TRUE(first.sourceSeriesUid.empty());
    EXPECT_TRUE(volumes::isValidDicomUid(first.studyInstanceUid));
    EXPECT_NE(first.studyInstanceUid, second.studyInstanceUid);  // each render its own study
    EXPECT_FALSE(volumes::isValidDicomUid("1.2.03.4"));            // a leading zero
    EXPECT_FALSE(volumes::isValidDicomUid("1.2.abc"));
}

}  // namespace
