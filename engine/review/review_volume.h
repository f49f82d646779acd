/// @brief The CT as the review page ships it: reduced by box filtering to a size a browser reads
/// at once, windowed to 8 bits, with the three orthogonal slice views (axial, coronal, sagittal)
/// oriented by the radiological convention from the scan's patient orientation.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "volumes/volume.h"

namespace engine {

/// Window of the shipped slices, in Hounsfield units. The colon is read on CT colonography with
/// a wide "lung" window: air in the lumen black, fat, wall and polyps grey, fluid and bone light,
/// so the lumen's edge and what bulges into it both show. -950..550 HU.
inline constexpr double kReviewWindowWidthHu = 1500.0;
inline constexpr double kReviewWindowLevelHu = -200.0;
/// Longest side of the shipped grid in voxels: 160^3 bytes is 4 MB, 5.5 MB of base64, which a
/// browser decodes in a blink from the file system.
inline constexpr int kReviewMaxSide = 160;

/// One slice view of the reduced grid. Image column c shows grid index c along `columnAxis`
/// (counted from the far end when `isColumnFlipped`), image row r index r along `rowAxis` (from
/// the far end when `isRowFlipped`), slices are taken across `normalAxis`. The edge labels name
/// the patient direction that lies toward each edge of the image (R, L, A, P, S, I).
struct ReviewSliceView {
    std::string name;  // "axial", "coronal", "sagittal"
    int normalAxis = 2;
    int columnAxis = 0;
    int rowAxis = 1;
    bool isColumnFlipped = false;
    bool isRowFlipped = false;
    std::string leftLabel, rightLabel, topLabel, bottomLabel;
};

/// The reduced, windowed CT. Reduced voxel (i, j, k) averages the original voxels
/// factor * (i, j, k) .. factor * (i, j, k) + factor - 1 (fewer at the far faces); its centre
/// lies at offsetMm + (i, j, k) * spacingMm in volume millimetres.
struct ReviewVolume {
    std::array<int, 3> dims{0, 0, 0};
    std::array<int, 3> factor{1, 1, 1};
    glm::dvec3 spacingMm{1.0};
    glm::dvec3 offsetMm{0.0};
    double windowWidthHu = kReviewWindowWidthHu;
    double windowLevelHu = kReviewWindowLevelHu;
    std::vector<uint8_t> grey;  // x fastest, as volumes::Volume
    std::array<ReviewSliceView, 3> views;
    glm::dmat3 directionLps{1.0};  // the scan's orientation (volumes::Volume), for patient directions
    /// True when a grid axis lies more than about 8 degrees off the patient axis it is shown as:
    /// the labels then name the nearest patient direction.
    bool isOblique = false;
};

/// Grey level of `hu` through the review window: 0 at level - width / 2, 255 at level + width / 2.
uint8_t reviewGrey(double hu);

/// `volume` box-filtered along each axis by the smallest integer factor that brings it to at most
/// `maxSide` voxels, windowed, with its slice views. Throws std::invalid_argument for an empty
/// volume or a maxSide below 1.
ReviewVolume reviewVolumeOf(const volumes::Volume& volume, int maxSide = kReviewMaxSide);

/// The three views for a grid whose axes point along the columns of `directionLps` (patient LPS):
/// axial seen from the feet (patient's right on the image's left, anterior up), coronal seen from
/// the front (right on the left, superior up), sagittal seen from the patient's left (anterior on
/// the left, superior up). Each patient axis goes to the grid axis nearest to it.
std::array<ReviewSliceView, 3> reviewSliceViews(const glm::dmat3& directionLps, bool* isOblique = nullptr);

/// Standard base64 (RFC 4648, with padding) of `bytes`.
std::string base64Of(const std::vector<uint8_t>& bytes);

}  // namespace engine
