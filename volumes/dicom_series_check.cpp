/// @brief Checks of the values GDCM hands the DICOM reader, and the series grid (dicom_series_check.h).
#include "volumes/dicom_series_check.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>

namespace volumes {
namespace {

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

/// Orders slices along the normal and checks that they form one regular grid. Returns the
/// slice spacing in mm.
double sortAndCheckSlices(const std::string& folder, std::vector<DicomSlice>& slices, glm::dvec3& normal,
                          double inPlaneSpacingMm) {
    // Sorting by a NaN distance would break std::sort's ordering: refuse non-finite values first.
    const auto isFinite = [](const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    for (const DicomSlice& slice : slices) {
        if (!isFinite(slice.positionLps) || !isFinite(slice.rowLps) || !isFinite(slice.columnLps)) {
            fail(slice.path, "ImagePositionPatient or ImageOrientationPatient is not finite");
        }
    }
    const DicomSlice& first = slices.front();
    const double rowLength = glm::length(first.rowLps), columnLength = glm::length(first.columnLps);
    if (std::abs(rowLength - 1.0) > 1e-2 || std::abs(columnLength - 1.0) > 1e-2 ||
        std::abs(glm::dot(first.rowLps, first.columnLps)) > 1e-2) {
        fail(first.path, "ImageOrientationPatient is not two orthogonal unit vectors");
    }
    const glm::dvec3 row = glm::normalize(first.rowLps), column = glm::normalize(first.columnLps);
    normal = glm::normalize(glm::cross(row, column));
    for (DicomSlice& slice : slices) {
        if (glm::length(slice.rowLps - first.rowLps) > kOrientationTolerance ||
            glm::length(slice.columnLps - first.columnLps) > kOrientationTolerance) {
            fail(slice.path, "ImageOrientationPatient differs from that of " + first.path +
                                 " (one series must share one orientation)");
        }
        slice.distanceMm = glm::dot(normal, slice.positionLps);
    }
    std::sort(slices.begin(), slices.end(),
              [](const DicomSlice& a, const DicomSlice& b) { return a.distanceMm < b.distanceMm; });
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
    for (const DicomSlice& slice : slices) {
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

}  // namespace

Volume dicomSeriesGrid(const std::string& folder, const DicomImageValues& first, std::vector<DicomSlice>& slices) {
    if (slices.empty()) fail(folder, "holds no slice of the series");
    if (first.numberOfDimensions == 3 && first.dims[2] > 1) {
        fail(slices.front().path, "is a multi-frame image (" + std::to_string(first.dims[2]) +
                                      " frames); only series stored one slice per file are supported");
    }
    // Sizes beyond the limit would not fit int: refuse them before converting.
    for (std::size_t axis = 0; axis < 2; ++axis) {
        if (first.dims[axis] < 1 || first.dims[axis] > static_cast<unsigned>(kMaxDimension)) {
            fail(slices.front().path, std::string(axis == 0 ? "Columns" : "Rows") + " is " +
                                          std::to_string(first.dims[axis]) + ", expected 1.." +
                                          std::to_string(kMaxDimension));
        }
    }
    if (slices.size() > static_cast<std::size_t>(kMaxDimension)) {
        fail(folder, "holds " + std::to_string(slices.size()) + " slices of one series, more than " +
                         std::to_string(kMaxDimension));
    }
    Volume volume;
    volume.dims = {static_cast<int>(first.dims[0]), static_cast<int>(first.dims[1]), static_cast<int>(slices.size())};
    volume.spacingMm = {first.spacingMm[0], first.spacingMm[1], first.spacingMm[2]};
    glm::dvec3 normal{0, 0, 1};
    const double sliceSpacing = sortAndCheckSlices(folder, slices, normal, std::min(volume.spacingMm.x, volume.spacingMm.y));
    if (slices.size() > 1) volume.spacingMm.z = sliceSpacing;
    const DicomSlice& front = slices.front();
    volume.originLps = front.positionLps;
    volume.directionLps = glm::dmat3(glm::normalize(front.rowLps), glm::normalize(front.columnLps), normal);
    validateGeometry(volume, folder);
    return volume;
}

StoredFormat dicomSliceFormat(const std::string& path, const Volume& grid, const DicomImageValues& image) {
    if (image.dims[0] != static_cast<unsigned>(grid.dims[0]) || image.dims[1] != static_cast<unsigned>(grid.dims[1])) {
        fail(path, "is " + std::to_string(image.dims[0]) + "x" + std::to_string(image.dims[1]) +
                       " pixels, the series' first slice " + std::to_string(grid.dims[0]) + "x" +
                       std::to_string(grid.dims[1]));
    }
    if (!(std::abs(image.spacingMm[0] - grid.spacingMm.x) <= 1e-4) ||
        !(std::abs(image.spacingMm[1] - grid.spacingMm.y) <= 1e-4)) {
        fail(path, "PixelSpacing differs from the series' first slice");
    }
    if (image.samplesPerPixel != 1) {
        fail(path, "has " + std::to_string(image.samplesPerPixel) + " samples per pixel, expected 1 (grey CT)");
    }
    if (!image.type) {
        fail(path, "pixel format " + image.typeName + " is not supported (expected 8, 16 or 32-bit integers)");
    }
    StoredFormat format;
    format.type = *image.type;
    if (!std::isfinite(image.slope) || !std::isfinite(image.intercept)) {
        std::ostringstream msg;
        msg << "RescaleSlope " << image.slope << " and RescaleIntercept " << image.intercept << " must be finite";
        fail(path, msg.str());
    }
    format.slope = image.slope;
    format.intercept = image.intercept;
    const std::size_t expectedBytes = static_cast<std::size_t>(grid.dims[0]) * static_cast<std::size_t>(grid.dims[1]) *
                                      bytesPerValue(format.type);
    if (image.bufferBytes != expectedBytes) {
        fail(path, "pixel data decodes to " + std::to_string(image.bufferBytes) + " bytes, expected " +
                       std::to_string(expectedBytes));
    }
    return format;
}

void maskStoredBits(unsigned bitsStored, ScalarType type, std::span<unsigned char> buffer) {
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

}  // namespace volumes
