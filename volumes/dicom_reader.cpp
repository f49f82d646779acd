#include "volumes/dicom_reader.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
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
/// Direction cosines of different slices agree when within this (unitless).
constexpr double kOrientationTolerance = 1e-4;
/// Slice gaps may differ from their mean by this fraction (rounded positions) before the
/// series counts as unevenly spaced.
constexpr double kGapTolerance = 0.01;
/// A slice may sit off the line through the first slice along the normal by this fraction of
/// the in-plane spacing before the series counts as tilted: below it the grid error is
/// invisible next to the voxel size.
constexpr double kTiltLateralTolerance = 0.25;

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

struct SliceFile {
    std::string path;
    glm::dvec3 positionLps{0.0};
    glm::dvec3 rowLps{1, 0, 0}, columnLps{0, 1, 0};
    double distanceMm = 0.0;  ///< position projected on the slice normal
};

/// All readable image files in `folder`, grouped by series UID.
std::map<std::string, std::vector<SliceFile>> scanFolder(const std::string& folder) {
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

    std::map<std::string, std::vector<SliceFile>> series;
    for (const std::string& path : files) {
        if (!scanner.IsKey(path.c_str())) continue;
        SliceFile slice;
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

/// Orders slices along the normal and checks that they form one regular grid. Returns the
/// slice spacing in mm.
double sortAndCheckSlices(const std::string& folder, std::vector<SliceFile>& slices, glm::dvec3& normal,
                          double inPlaneSpacingMm) {
    const SliceFile& first = slices.front();
    const double rowLength = glm::length(first.rowLps), columnLength = glm::length(first.columnLps);
    if (std::abs(rowLength - 1.0) > 1e-2 || std::abs(columnLength - 1.0) > 1e-2 ||
        std::abs(glm::dot(first.rowLps, first.columnLps)) > 1e-2) {
        fail(first.path, "ImageOrientationPatient is not two orthogonal unit vectors");
    }
    const glm::dvec3 row = glm::normalize(first.rowLps), column = glm::normalize(first.columnLps);
    normal = glm::normalize(glm::cross(row, column));
    for (SliceFile& slice : slices) {
        if (glm::length(slice.rowLps - first.rowLps) > kOrientationTolerance ||
            glm::length(slice.columnLps - first.columnLps) > kOrientationTolerance) {
            fail(slice.path, "ImageOrientationPatient differs from that of " + first.path +
                                 " (one series must share one orientation)");
        }
        slice.distanceMm = glm::dot(normal, slice.positionLps);
    }
    std::sort(slices.begin(), slices.end(),
              [](const SliceFile& a, const SliceFile& b) { return a.distanceMm < b.distanceMm; });
    if (slices.size() < 2) return 0.0;

    const double spanMm = slices.back().distanceMm - slices.front().distanceMm;
    const double spacingMm = spanMm / static_cast<double>(slices.size() - 1);
    // Duplicates first: they would otherwise read as uneven spacing.
    for (std::size_t k = 1; k < slices.size(); ++k) {
        if (slices[k].distanceMm - slices[k - 1].distanceMm < 1e-3) {
            fail(folder, slices[k - 1].path + " and " + slices[k].path +
                             " lie at the same position along the slice normal (several acquisitions in one "
                             "series? pass the series or split the folder)");
        }
    }
    for (std::size_t k = 1; k < slices.size(); ++k) {
        const double gap = slices[k].distanceMm - slices[k - 1].distanceMm;
        if (std::abs(gap - spacingMm) > kGapTolerance * spacingMm) {
            std::ostringstream msg;
            msg << "uneven slice spacing: " << gap << " mm between " << slices[k - 1].path << " and " << slices[k].path
                << ", mean " << spacingMm << " mm (missing slice or variable-thickness "
                << "scan; resample it to a regular grid first)";
            fail(folder, msg.str());
        }
    }
    // Gantry tilt: slice origins leave the line along the normal through the first one.
    for (const SliceFile& slice : slices) {
        const glm::dvec3 offset = slice.positionLps - slices.front().positionLps;
        const glm::dvec3 lateral = offset - glm::dot(offset, normal) * normal;
        if (glm::length(lateral) > kTiltLateralTolerance * inPlaneSpacingMm) {
            const double degrees =
                std::atan2(glm::length(lateral), std::abs(glm::dot(offset, normal))) * 180.0 / 3.14159265358979;
            std::ostringstream msg;
            msg << "slices are sheared (gantry tilt of about " << degrees << " degrees: " << slice.path << " sits "
                << glm::length(lateral) << " mm off the slice normal); resample the series "
                << "to an orthogonal grid first";
            fail(folder, msg.str());
        }
    }
    return spacingMm;
}

/// Stored-value format of a slice as GDCM hands out its buffer.
StoredFormat formatOf(const std::string& path, const gdcm::Image& image) {
    const gdcm::PixelFormat& pixel = image.GetPixelFormat();
    if (pixel.GetSamplesPerPixel() != 1) {
        fail(path, "has " + std::to_string(pixel.GetSamplesPerPixel()) + " samples per pixel, expected 1 (grey CT)");
    }
    StoredFormat format;
    switch (pixel.GetScalarType()) {
        case gdcm::PixelFormat::UINT8: format.type = ScalarType::UInt8; break;
        case gdcm::PixelFormat::INT8: format.type = ScalarType::Int8; break;
        case gdcm::PixelFormat::UINT16: format.type = ScalarType::UInt16; break;
        case gdcm::PixelFormat::INT16: format.type = ScalarType::Int16; break;
        case gdcm::PixelFormat::UINT32: format.type = ScalarType::UInt32; break;
        case gdcm::PixelFormat::INT32: format.type = ScalarType::Int32; break;
        case gdcm::PixelFormat::FLOAT32: format.type = ScalarType::Float32; break;
        case gdcm::PixelFormat::FLOAT64: format.type = ScalarType::Float64; break;
        default:
            fail(path, std::string("pixel format ") + pixel.GetScalarTypeAsString() +
                           " is not supported (expected 8, 16 or 32-bit integers)");
    }
    format.slope = image.GetSlope();
    format.intercept = image.GetIntercept();
    return format;
}

/// Clears bits above BitsStored and sign-extends signed values, so overlay bits or padding
/// in the unused high bits of a 16-bit container cannot reach the HU values.
void maskStoredBits(const gdcm::PixelFormat& pixel, ScalarType type, std::vector<char>& buffer) {
    const unsigned bitsStored = pixel.GetBitsStored();
    if (type != ScalarType::UInt16 && type != ScalarType::Int16) return;
    if (bitsStored == 0 || bitsStored >= 16) return;
    const auto mask = static_cast<uint16_t>((1u << bitsStored) - 1u);
    const auto sign = static_cast<uint16_t>(1u << (bitsStored - 1u));
    for (std::size_t i = 0; i + 1 < buffer.size(); i += 2) {
        uint16_t v;
        std::memcpy(&v, buffer.data() + i, 2);
        v = static_cast<uint16_t>(v & mask);
        if (type == ScalarType::Int16 && (v & sign)) v = static_cast<uint16_t>(v | ~mask);
        std::memcpy(buffer.data() + i, &v, 2);
    }
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
    std::vector<SliceFile>* slices = nullptr;
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
    const gdcm::Image& firstImage = firstReader.GetImage();
    const unsigned int* firstDims = firstImage.GetDimensions();
    if (firstImage.GetNumberOfDimensions() == 3 && firstDims[2] > 1) {
        fail(slices->front().path, "is a multi-frame image (" + std::to_string(firstDims[2]) +
                                       " frames); only series stored one slice per file are supported");
    }

    Volume volume;
    volume.dims = {static_cast<int>(firstDims[0]), static_cast<int>(firstDims[1]), static_cast<int>(slices->size())};
    volume.spacingMm = {firstImage.GetSpacing(0), firstImage.GetSpacing(1), firstImage.GetSpacing(2)};
    glm::dvec3 normal{0, 0, 1};
    const double sliceSpacing =
        sortAndCheckSlices(folder, *slices, normal, std::min(volume.spacingMm.x, volume.spacingMm.y));
    if (slices->size() > 1) volume.spacingMm.z = sliceSpacing;
    const SliceFile& first = slices->front();
    volume.originLps = first.positionLps;
    volume.directionLps = glm::dmat3(glm::normalize(first.rowLps), glm::normalize(first.columnLps), normal);
    validateGeometry(volume, folder);

    // Voxels: one slice at a time into the volume.
    volume.hu.resize(volume.voxelCount());
    const std::size_t sliceVoxels = static_cast<std::size_t>(volume.dims[0]) * static_cast<std::size_t>(volume.dims[1]);
    std::vector<char> buffer;
    const std::size_t fileCount = slices->size();
    for (std::size_t k = 0; k < fileCount; ++k) {
        const SliceFile& slice = (*slices)[k];
        gdcm::ImageReader reader;
        readImage(slice.path, reader);
        const gdcm::Image& image = reader.GetImage();
        const unsigned int* dims = image.GetDimensions();
        if (dims[0] != firstDims[0] || dims[1] != firstDims[1]) {
            fail(slice.path, "is " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) +
                                 " pixels, the series' first slice " + std::to_string(firstDims[0]) + "x" +
                                 std::to_string(firstDims[1]));
        }
        if (std::abs(image.GetSpacing(0) - volume.spacingMm.x) > 1e-4 ||
            std::abs(image.GetSpacing(1) - volume.spacingMm.y) > 1e-4) {
            fail(slice.path, "PixelSpacing differs from the series' first slice");
        }
        const StoredFormat format = formatOf(slice.path, image);
        const std::size_t expectedBytes = sliceVoxels * bytesPerValue(format.type);
        if (image.GetBufferLength() != expectedBytes) {
            fail(slice.path, "pixel data decodes to " + std::to_string(image.GetBufferLength()) + " bytes, expected " +
                                 std::to_string(expectedBytes));
        }
        buffer.resize(expectedBytes);
        if (!image.GetBuffer(buffer.data())) {
            fail(slice.path, "GDCM cannot decode its pixel data (transfer syntax unsupported or data corrupt)");
        }
        maskStoredBits(image.GetPixelFormat(), format.type, buffer);
        huFromStored(slice.path, format, reinterpret_cast<const unsigned char*>(buffer.data()),
                     std::span<int16_t>(volume.hu).subspan(k * sliceVoxels, sliceVoxels));
    }
    validateVolume(volume, folder);
    return volume;
}

}  // namespace volumes
