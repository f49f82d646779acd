/// @brief Rendered pictures going back to PACS: each image written as a DICOM Secondary
/// Capture (RGB, 8 bits) that carries the source series' patient and study identifiers, in a new
/// series with new UIDs. Written and read through GDCM.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace volumes {

/// The patient and study a picture belongs to, as the source series says them.
struct DicomIdentifiers {
    std::string patientName;
    std::string patientId;
    std::string patientBirthDate;
    std::string patientSex;
    std::string studyInstanceUid;
    std::string studyId;
    std::string studyDate;
    std::string studyTime;
    std::string accessionNumber;
    std::string studyDescription;
    std::string referringPhysicianName;
    std::string sourceSeriesUid;  // the series the pictures were rendered from; empty for placeholders
    bool isPlaceholder = false;   // the source was not DICOM: clearly marked stand-ins, a new study
};

/// The placeholder's patient name and ID: no PACS will take them for a real patient's.
inline constexpr const char* kPlaceholderPatientName = "CVC^NO DICOM SOURCE";
inline constexpr const char* kPlaceholderPatientId = "CVC-NO-DICOM-SOURCE";

/// The identifiers of the DICOM series `volumePath` is read from: a folder's series
/// `seriesUid`, or its largest as readDicomSeries chooses. Any other source (a file: NRRD, NIfTI,
/// MetaImage, raw, VDB, or a phantom) gets placeholders (isPlaceholder) with a new study UID.
/// Throws VolumeError for a folder without a readable series.
DicomIdentifiers dicomIdentifiersOf(const std::string& volumePath, const std::string& seriesUid = {});

/// A new, globally unique DICOM UID (GDCM's generator).
std::string newDicomUid();

/// Whether `uid` is a valid DICOM UID (digits and dots, at most 64 characters, no leading zeros).
bool isValidDicomUid(const std::string& uid);

/// One picture of a new series.
struct SecondaryCapture {
    DicomIdentifiers identifiers;
    std::string seriesInstanceUid;   // shared by the series' pictures (newDicomUid)
    int seriesNumber = 1;
    std::string seriesDescription;   // what the series shows: display, frame, eye
    int instanceNumber = 1;
    std::string imageComments;       // what this picture is: the wall, the sheet
};

/// Writes `rgba` (width x height, 4 bytes a pixel, rows top to bottom) as a Secondary Capture
/// Image Storage file at `path` (explicit VR little endian, RGB; alpha dropped) with a new SOP
/// instance UID, which it returns. Throws std::runtime_error naming the file when it exists and
/// `force` is false or the write fails, std::invalid_argument for a size the pixels do not match.
std::string writeSecondaryCapture(const std::string& path, int width, int height, const std::vector<uint8_t>& rgba,
                                  const SecondaryCapture& capture, bool force);

/// A Secondary Capture file as read back: its pixels as RGB and the identifiers it carries.
struct SecondaryCaptureFile {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> rgb;  // rows top to bottom, 3 bytes a pixel
    std::string sopClassUid;
    std::string sopInstanceUid;
    std::string seriesInstanceUid;
    std::string studyInstanceUid;
    std::string patientName;
    std::string patientId;
    std::string seriesDescription;
};

/// Reads a file writeSecondaryCapture wrote (or any 8-bit RGB DICOM image) through GDCM. Throws
/// std::runtime_error naming the file when GDCM cannot read it or it is not 8-bit RGB.
SecondaryCaptureFile readSecondaryCapture(const std::string& path);

}  // namespace volumes
