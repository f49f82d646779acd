/// @brief The checks the DICOM reader applies to the values GDCM hands it (slice positions and
/// orientations, rows, columns and frames, pixel spacing, the pixel format, rescale slope and
/// intercept, bits stored, decoded byte counts), and the grid it derives from them. Pure (no
/// GDCM), so the same functions serve the reader and its fuzz target.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "volumes/volume.h"
#include "volumes/voxel_decode.h"

namespace volumes {

/// One image file of a series as the folder scan found it (ImagePositionPatient and
/// ImageOrientationPatient, LPS).
struct DicomSlice {
    std::string path;
    glm::dvec3 positionLps{0.0};
    glm::dvec3 rowLps{1, 0, 0}, columnLps{0, 1, 0};
    double distanceMm = 0.0;  ///< position projected on the slice normal (set by dicomSeriesGrid)
};

/// What GDCM reports for one image file.
struct DicomImageValues {
    unsigned numberOfDimensions = 2;
    std::array<unsigned, 3> dims{0, 0, 1};      ///< columns, rows, frames
    std::array<double, 3> spacingMm{1, 1, 1};   ///< PixelSpacing (column, row) and slice spacing
    unsigned samplesPerPixel = 1;
    std::optional<ScalarType> type;             ///< empty: a pixel format the reader does not take
    std::string typeName;                       ///< GDCM's name for the pixel format, for messages
    unsigned bitsStored = 16;
    double slope = 1.0;
    double intercept = 0.0;
    std::size_t bufferBytes = 0;                ///< what the pixel data decode to
};

/// The grid of a series from its first image and its slices, which it sorts by their position
/// along the slice normal row x column. Refuses multi-frame images, orientations that are not
/// two orthogonal unit vectors or that differ between slices, duplicate or uneven slice
/// positions, gantry tilt, and grids validateGeometry refuses. Throws VolumeError naming the file
/// or `folder`.
Volume dicomSeriesGrid(const std::string& folder, const DicomImageValues& first, std::vector<DicomSlice>& slices);

/// Checks one slice's image against the series' grid (size and pixel spacing), its pixel format
/// (one sample, a supported scalar type, finite rescale values) and the decoded byte count;
/// returns its stored format. Throws VolumeError naming `path`.
StoredFormat dicomSliceFormat(const std::string& path, const Volume& grid, const DicomImageValues& image);

/// Clears bits above `bitsStored` of 16-bit values and sign-extends signed ones, so overlay
/// bits or padding in the unused high bits of a 16-bit container cannot reach the HU values.
void maskStoredBits(unsigned bitsStored, ScalarType type, std::span<unsigned char> buffer);

}  // namespace volumes
