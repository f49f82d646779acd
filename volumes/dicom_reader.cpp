#include "volumes/dicom_reader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>

#include <gdcmDirectory.h>
#include <gdcmImage.h>
#include <gdcmImageReader.h>
#include <gdcmPhotometricInterpretation.h>
#include <gdcmPixelFormat.h>
#include <gdcmScanner.h>
#include <gdcmTag.h>
#include <gdcmTrace.h>

#include "volumes/dicom_series_check.h"
#include "volumes/voxel_decode.h"

namespace volumes {
namespace {

const gdcm::Tag kSeriesUid(0x0020, 0x000e);
const gdcm::Tag kImagePosition(0x0020, 0x0032);
const gdcm::Tag kImageOrientation(0x0020, 0x0037);
const gdcm::Tag kRows(0x0028, 0x0010);
const gdcm::Tag kColumns(0x0028, 0x0011);

/// A folder with more files than this is not one CT study.
constexpr std::size_t kMaxFiles = 100000;
[[noreturn]] void fail(const std::string& where, const std::string& problem) {
    throw VolumeError(where + ": " + problem);
}

/// Parses the backslash-separated decimal strings of a DS value into exactly `count` numbers.
bool parseDecimals(const char* text, std::size_t count, double* out) {
    if (text == nullptr) return false;
    std::string s(text);
    std::replace(s.begin(), s.end(), '\\', ' ');
    std::istringstream in(s);
    in.imbue(std::locale::classic());
    for (std::size_t i = 0; i < count; ++i) {
        if (!(in >> out[i]) || !std::isfinite(out[i])) return false;
    }
    return true;
}

std::string trimmed(const char* text) {
    std::string s = text ? text : "";
    while (!s.empty() && (s.back() == ' ' || s.back() == '\0')) s.pop_back();
    return s;
}

/// All readable image files in `folder`, grouped by series UID.
std::map<std::string, std::vector<DicomSlice>> scanFolder(const std::string& folder) {
    std::error_code error;
    if (!std::filesystem::is_directory(folder, error))
        fail(folder, "is not a folder (a DICOM series is read from a folder)");
    gdcm::Trace::SetWarning(false);
    gdcm::Directory directory;
    directory.Load(folder, true);
    const gdcm::Directory::FilenamesType& files = directory.GetFilenames();
    if (files.empty()) fail(folder, "is empty (expected the DICOM files of a CT series)");
    if (files.size() > kMaxFiles) {
        fail(folder, "holds " + std::to_string(files.size()) + " files, more than " + std::to_string(kMaxFiles) +
                         " (point at one series' folder)");
    }
    gdcm::Scanner scanner;
    for (const gdcm::Tag& tag : {kSeriesUid, kImagePosition, kImageOrientation, kRows, kColumns}) scanner.AddTag(tag);
    if (!scanner.Scan(files)) fail(folder, "GDCM could not scan the folder's files");

    std::map<std::string, std::vector<DicomSlice>> series;
    for (const std::string& path : files) {
        if (!scanner.IsKey(path.c_str())) continue;
        DicomSlice slice;
        slice.path = path;
        double position[3], orientation[6];
        if (!parseDecimals(scanner.GetValue(path.c_str(), kImagePosition), 3, position) ||
            !parseDecimals(scanner.GetValue(path.c_str(), kImageOrientation), 6, orientation) ||
            scanner.GetValue(path.c_str(), kRows) == nullptr) {
            continue;  // not an image slice with a place in the patient (a report, a DICOMDIR, ...)
        }
        slice.positionLps = {position[0], position[1], position[2]};
        slice.rowLps = {orientation[0], orientation[1], orientation[2]};
        slice.columnLps = {orientation[3], orientation[4], orientation[5]};
        series[trimmed(scanner.GetValue(path.c_str(), kSeriesUid))].push_back(std::move(slice));
    }
    if (series.empty()) {
        fail(folder, "holds " + std::to_string(files.size()) +
                         " files but no DICOM image with ImagePositionPatient and ImageOrientationPatient");
    }
    return series;
}

/// The values of one decoded image that the series checks need (dicom_series_check.h).
DicomImageValues imageValues(const gdcm::Image& image) {
    DicomImageValues values;
    values.numberOfDimensions = image.GetNumberOfDimensions();
    const unsigned int* dims = image.GetDimensions();
    values.dims = {dims[0], dims[1], values.numberOfDimensions == 3 ? dims[2] : 1u};
    values.spacingMm = {image.GetSpacing(0), image.GetSpacing(1), image.GetSpacing(2)};
    const gdcm::PixelFormat& pixel = image.GetPixelFormat();
    values.samplesPerPixel = pixel.GetSamplesPerPixel();
    switch (pixel.GetScalarType()) {
        case gdcm::PixelFormat::UINT8: values.type = ScalarType::UInt8; break;
        case gdcm::PixelFormat::INT8: values.type = ScalarType::Int8; break;
        case gdcm::PixelFormat::UINT16: values.type = ScalarType::UInt16; break;
        case gdcm::PixelFormat::INT16: values.type = ScalarType::Int16; break;
        case gdcm::PixelFormat::UINT32: values.type = ScalarType::UInt32; break;
        case gdcm::PixelFormat::INT32: values.type = ScalarType::Int32; break;
        case gdcm::PixelFormat::FLOAT32: values.type = ScalarType::Float32; break;
        case gdcm::PixelFormat::FLOAT64: values.type = ScalarType::Float64; break;
        default: break;
    }
    values.typeName = pixel.GetScalarTypeAsString();
    values.bitsStored = pixel.GetBitsStored();
    values.slope = image.GetSlope();
    values.intercept = image.GetIntercept();
    values.bufferBytes = image.GetBufferLength();
    return values;
}

/// Reads one file. GDCM accepts a file whose native pixel data end early (it only warns), so
/// its warnings are captured while reading and that one is turned into an error.
void readImage(const std::string& path, gdcm::ImageReader& reader) {
    std::ostringstream warnings;
    gdcm::Trace::SetWarningStream(warnings);
    gdcm::Trace::SetWarning(true);
    struct Restore {
        ~Restore() {
            gdcm::Trace::SetWarning(false);
            gdcm::Trace::SetWarningStream(std::cerr);
        }
    } restore;
    reader.SetFileName(path.c_str());
    if (!reader.Read()) fail(path, "GDCM cannot read it as a DICOM image (corrupt or truncated?)");
    if (warnings.str().find("Incomplete Pixel Data") != std::string::npos) {
        fail(path, "pixel data are truncated (the file ends before the image does)");
    }
}

}  // namespace

std::vector<DicomSeriesInfo> listDicomSeries(const std::string& folder) {
    std::vector<DicomSeriesInfo> list;
    for (const auto& [uid, slices] : scanFolder(folder)) list.push_back({uid, slices.size()});
    std::stable_sort(list.begin(), list.end(),
                     [](const DicomSeriesInfo& a, const DicomSeriesInfo& b) { return a.fileCount > b.fileCount; });
    return list;
}

Volume readDicomSeries(const std::string& folder, const std::string& seriesUid) {
    auto series = scanFolder(folder);

    // Pick the series.
    std::vector<DicomSlice>* slices = nullptr;
    if (!seriesUid.empty()) {
        const auto it = series.find(seriesUid);
        if (it == series.end()) fail(folder, "holds no series with SeriesInstanceUID " + seriesUid);
        slices = &it->second;
    } else {
        std::size_t largest = 0, ties = 0;
        for (auto& [uid, files] : series) {
            if (files.size() > largest) {
                largest = files.size();
                slices = &files;
                ties = 1;
            } else if (files.size() == largest) {
                ++ties;
            }
        }
        if (ties > 1) {
            std::string names;
            for (const auto& [uid, files] : series)
                names += " " + uid + " (" + std::to_string(files.size()) + " files)";
            fail(folder, "holds several series of equal size, name one:" + names);
        }
    }

    // One slice fixes the in-plane grid every other slice must share.
    gdcm::ImageReader firstReader;
    readImage(slices->front().path, firstReader);
    Volume volume = dicomSeriesGrid(folder, imageValues(firstReader.GetImage()), *slices);

    // Voxels: one slice at a time into the volume.
    volume.hu.resize(volume.voxelCount());
    const std::size_t sliceVoxels = static_cast<std::size_t>(volume.dims[0]) * static_cast<std::size_t>(volume.dims[1]);
    std::vector<char> buffer;
    const std::size_t fileCount = slices->size();
    for (std::size_t k = 0; k < fileCount; ++k) {
        const DicomSlice& slice = (*slices)[k];
        gdcm::ImageReader reader;
        readImage(slice.path, reader);
        const gdcm::Image& image = reader.GetImage();
        const DicomImageValues values = imageValues(image);
        const StoredFormat format = dicomSliceFormat(slice.path, volume, values);
        buffer.resize(values.bufferBytes);
        if (!image.GetBuffer(buffer.data())) {
            fail(slice.path, "GDCM cannot decode its pixel data (transfer syntax unsupported or data corrupt)");
        }
        const std::span<unsigned char> bytes(reinterpret_cast<unsigned char*>(buffer.data()), buffer.size());
        maskStoredBits(values.bitsStored, format.type, bytes);
        huFromStored(slice.path, format, bytes.data(), std::span<int16_t>(volume.hu).subspan(k * sliceVoxels, sliceVoxels));
    }
    validateVolume(volume, folder);
    return volume;
}

}  // namespace volumes
