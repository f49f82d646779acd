#include "volumes/dicom_secondary_capture.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include <gdcmAttribute.h>
#include <gdcmDirectory.h>
#include <gdcmImageReader.h>
#include <gdcmImageWriter.h>
#include <gdcmReader.h>
#include <gdcmScanner.h>
#include <gdcmStringFilter.h>
#include <gdcmTrace.h>
#include <gdcmUIDGenerator.h>

#include "volumes/dicom_reader.h"
#include "volumes/volume.h"

namespace volumes {
namespace {

namespace fs = std::filesystem;

const gdcm::Tag kSeriesUid(0x0020, 0x000e);

/// A DICOM string value without the padding (spaces, and the zero byte of UIDs).
std::string trimmedValue(const std::string& text) {
    const std::size_t end = text.find_last_not_of(std::string(" \0", 2));
    return end == std::string::npos ? std::string() : text.substr(0, end + 1);
}

/// The text of a data set's tags, without the padding, as GDCM's string filter gives them.
class TagText {
public:
    explicit TagText(gdcm::File& file) { mStrings.SetFile(file); }
    std::string operator()(uint16_t group, uint16_t element) const {
        return trimmedValue(mStrings.ToString(gdcm::Tag(group, element)));
    }

private:
    gdcm::StringFilter mStrings;
};

/// The first file (by name) of series `seriesUid` in `folder`.
std::string firstFileOfSeries(const std::string& folder, const std::string& seriesUid) {
    gdcm::Directory directory;
    directory.Load(folder, true);
    std::vector<std::string> files = directory.GetFilenames();
    std::sort(files.begin(), files.end());
    gdcm::Scanner scanner;
    scanner.AddTag(kSeriesUid);
    if (!scanner.Scan(files)) throw VolumeError(folder + ": GDCM could not scan the folder's files");
    for (const std::string& path : files) {
        const char* value = scanner.GetValue(path.c_str(), kSeriesUid);
        if (value != nullptr && trimmedValue(value) == seriesUid) return path;
    }
    throw VolumeError(folder + ": no file of series " + seriesUid);
}

template <uint16_t Group, uint16_t Element>
void setValue(gdcm::DataSet& dataSet, const std::string& value) {
    gdcm::Attribute<Group, Element> attribute;
    attribute.SetValue(value.c_str());
    dataSet.Replace(attribute.GetAsDataElement());
}

template <uint16_t Group, uint16_t Element>
void setNumber(gdcm::DataSet& dataSet, int value) {
    gdcm::Attribute<Group, Element> attribute;
    attribute.SetValue(value);
    dataSet.Replace(attribute.GetAsDataElement());
}

}  // namespace

std::string newDicomUid() {
    gdcm::UIDGenerator generator;
    const char* uid = generator.Generate();
    if (uid == nullptr) throw std::runtime_error("DICOM: GDCM could not generate a UID");
    return uid;
}

bool isValidDicomUid(const std::string& uid) { return gdcm::UIDGenerator::IsValid(uid.c_str()); }

DicomIdentifiers dicomIdentifiersOf(const std::string& volumePath, const std::string& seriesUid) {
    DicomIdentifiers ids;
    std::error_code error;
    if (!fs::is_directory(volumePath, error)) {
        ids.isPlaceholder = true;
        ids.patientName = kPlaceholderPatientName;
        ids.patientId = kPlaceholderPatientId;
        ids.studyInstanceUid = newDicomUid();
        ids.studyDescription = "conformal-vc render of " + fs::path(volumePath).filename().string() +
                               " (not a DICOM source: placeholder patient and study)";
        return ids;
    }
    const std::vector<DicomSeriesInfo> series = listDicomSeries(volumePath);
    ids.sourceSeriesUid = seriesUid.empty() ? series.front().seriesUid : seriesUid;
    const std::string file = firstFileOfSeries(volumePath, ids.sourceSeriesUid);
    gdcm::Trace::SetWarning(false);
    gdcm::Reader reader;
    reader.SetFileName(file.c_str());
    if (!reader.Read()) throw VolumeError(file + ": GDCM could not read it");
    const TagText value(reader.GetFile());
    ids.patientName = value(0x0010, 0x0010);
    ids.patientId = value(0x0010, 0x0020);
    ids.patientBirthDate = value(0x0010, 0x0030);
    ids.patientSex = value(0x0010, 0x0040);
    ids.studyInstanceUid = value(0x0020, 0x000d);
    ids.studyId = value(0x0020, 0x0010);
    ids.studyDate = value(0x0008, 0x0020);
    ids.studyTime = value(0x0008, 0x0030);
    ids.accessionNumber = value(0x0008, 0x0050);
    ids.studyDescription = value(0x0008, 0x1030);
    ids.referringPhysicianName = value(0x0008, 0x0090);
    if (!isValidDicomUid(ids.studyInstanceUid)) {
        throw VolumeError(file + ": its StudyInstanceUID '" + ids.studyInstanceUid +
                          "' is not a valid UID; pictures cannot join its study");
    }
    return ids;
}

std::string writeSecondaryCapture(const std::string& path, int width, int height, const std::vector<uint8_t>& rgba,
                                  const SecondaryCapture& capture, bool force) {
    if (width <= 0 || height <= 0 ||
        rgba.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4) {
        throw std::invalid_argument(path + ": " + std::to_string(rgba.size()) + " bytes are not a " +
                                    std::to_string(width) + "x" + std::to_string(height) + " RGBA picture");
    }
    if (!force && fs::exists(path)) throw std::runtime_error(path + ": exists (use --force to replace it)");
    std::vector<char> rgb(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
    for (std::size_t pixel = 0, n = rgb.size() / 3; pixel < n; ++pixel) {
        for (std::size_t channel = 0; channel < 3; ++channel) rgb[pixel * 3 + channel] = static_cast<char>(rgba[pixel * 4 + channel]);
    }

    gdcm::ImageWriter writer;
    gdcm::Image& image = writer.GetImage();
    image.SetNumberOfDimensions(2);
    image.SetDimension(0, static_cast<unsigned int>(width));
    image.SetDimension(1, static_cast<unsigned int>(height));
    image.SetPixelFormat(gdcm::PixelFormat(3, 8, 8, 7, 0));
    image.SetPhotometricInterpretation(gdcm::PhotometricInterpretation::RGB);
    image.SetPlanarConfiguration(0);
    image.SetTransferSyntax(gdcm::TransferSyntax::ExplicitVRLittleEndian);
    gdcm::DataElement pixels(gdcm::Tag(0x7fe0, 0x0010));
    pixels.SetByteValue(rgb.data(), static_cast<uint32_t>(rgb.size()));
    image.SetDataElement(pixels);

    const DicomIdentifiers& ids = capture.identifiers;
    const std::string instanceUid = newDicomUid();
    gdcm::DataSet& dataSet = writer.GetFile().GetDataSet();
    setValue<0x0008, 0x0016>(dataSet, "1.2.840.10008.5.1.4.1.1.7");  // Secondary Capture Image Storage
    setValue<0x0008, 0x0018>(dataSet, instanceUid);
    setValue<0x0008, 0x0060>(dataSet, "OT");
    setValue<0x0008, 0x0064>(dataSet, "WSD");  // a workstation made it
    setValue<0x0008, 0x0070>(dataSet, "conformal-vc");
    setValue<0x0008, 0x103e>(dataSet, capture.seriesDescription);
    setValue<0x0010, 0x0010>(dataSet, ids.patientName);
    setValue<0x0010, 0x0020>(dataSet, ids.patientId);
    setValue<0x0010, 0x0030>(dataSet, ids.patientBirthDate);
    setValue<0x0010, 0x0040>(dataSet, ids.patientSex);
    setValue<0x0020, 0x000d>(dataSet, ids.studyInstanceUid);
    setValue<0x0020, 0x0010>(dataSet, ids.studyId);
    setValue<0x0008, 0x0020>(dataSet, ids.studyDate);
    setValue<0x0008, 0x0030>(dataSet, ids.studyTime);
    setValue<0x0008, 0x0050>(dataSet, ids.accessionNumber);
    setValue<0x0008, 0x1030>(dataSet, ids.studyDescription);
    setValue<0x0008, 0x0090>(dataSet, ids.referringPhysicianName);
    setValue<0x0020, 0x000e>(dataSet, capture.seriesInstanceUid);
    setNumber<0x0020, 0x0011>(dataSet, capture.seriesNumber);
    setNumber<0x0020, 0x0013>(dataSet, capture.instanceNumber);
    setValue<0x0020, 0x4000>(dataSet, capture.imageComments);
    if (!ids.sourceSeriesUid.empty()) {
        setValue<0x0008, 0x2111>(dataSet, "rendered from series " + ids.sourceSeriesUid);  // Derivation Description
    }

    const fs::path target(path);
    const fs::path partial = target.parent_path() / ("." + target.filename().string() + ".partial");
    writer.SetFileName(partial.c_str());
    if (!writer.Write()) {
        std::error_code ignored;
        fs::remove(partial, ignored);
        throw std::runtime_error(path + ": GDCM could not write the DICOM file");
    }
    std::error_code renameError;
    fs::rename(partial, target, renameError);
    if (renameError) throw std::runtime_error(path + ": cannot be written (" + renameError.message() + ")");
    return instanceUid;
}

SecondaryCaptureFile readSecondaryCapture(const std::string& path) {
    gdcm::ImageReader reader;
    reader.SetFileName(path.c_str());
    if (!reader.Read()) throw std::runtime_error(path + ": GDCM could not read it as a DICOM image");
    const gdcm::Image& image = reader.GetImage();
    const gdcm::PixelFormat& format = image.GetPixelFormat();
    if (image.GetPhotometricInterpretation() != gdcm::PhotometricInterpretation::RGB ||
        format.GetSamplesPerPixel() != 3 || format.GetBitsAllocated() != 8 || image.GetNumberOfDimensions() != 2) {
        throw std::runtime_error(path + ": is not an 8-bit RGB picture");
    }
    SecondaryCaptureFile file;
    file.width = static_cast<int>(image.GetDimension(0));
    file.height = static_cast<int>(image.GetDimension(1));
    file.rgb.resize(image.GetBufferLength());
    if (file.rgb.size() != static_cast<std::size_t>(file.width) * static_cast<std::size_t>(file.height) * 3 ||
        !image.GetBuffer(reinterpret_cast<char*>(file.rgb.data()))) {
        throw std::runtime_error(path + ": its pixel data could not be decoded");
    }
    if (image.GetPlanarConfiguration() != 0) throw std::runtime_error(path + ": planar RGB is not read here");
    const TagText value(reader.GetFile());
    file.sopClassUid = value(0x0008, 0x0016);
    file.sopInstanceUid = value(0x0008, 0x0018);
    file.seriesInstanceUid = value(0x0020, 0x000e);
    file.studyInstanceUid = value(0x0020, 0x000d);
    file.patientName = value(0x0010, 0x0010);
    file.patientId = value(0x0010, 0x0020);
    file.seriesDescription = value(0x0008, 0x103e);
    return file;
}

}  // namespace volumes
