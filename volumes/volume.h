/// @brief The one CT volume type every loader produces and every renderer consumes.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace volumes {

/// Bad or unsupported input data (a file, a header field, a voxel value). The message names
/// the file or field, the value found and what was expected; `cvc` prints it on one line.
class VolumeError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A CT volume in Hounsfield units.
///
/// Voxel (i, j, k) is stored at hu[i + dims[0] * (j + dims[1] * k)] (x fastest).
/// Two frames are used:
///  - *volume millimetres* (the renderer's frame): voxel (i, j, k) has its centre at
///    (i * spacingMm.x, j * spacingMm.y, k * spacingMm.z); axes follow the voxel grid.
///    Camera poses, hit positions and phantom ground truth are given in this frame.
///  - the *patient frame*, LPS as in DICOM (x to the patient's left, y posterior, z superior):
///    patient = originLps + directionLps * (spacingMm * index). Columns of directionLps are
///    unit vectors of the grid axes. Loaders of RAS formats (NIfTI) convert to LPS.
struct Volume {
    std::array<int, 3> dims{0, 0, 0};
    glm::dvec3 spacingMm{1.0, 1.0, 1.0};
    glm::dvec3 originLps{0.0, 0.0, 0.0};
    glm::dmat3 directionLps{1.0};
    std::vector<int16_t> hu;

    [[nodiscard]] std::size_t voxelCount() const {
        return static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) *
               static_cast<std::size_t>(dims[2]);
    }
    [[nodiscard]] std::size_t linearIndex(int i, int j, int k) const {
        return static_cast<std::size_t>(i) +
               static_cast<std::size_t>(dims[0]) *
                   (static_cast<std::size_t>(j) + static_cast<std::size_t>(dims[1]) * static_cast<std::size_t>(k));
    }
    [[nodiscard]] int16_t at(int i, int j, int k) const { return hu[linearIndex(i, j, k)]; }
    /// Size of the volume's box in volume millimetres (voxel centres span (dims-1)*spacing;
    /// the box adds half a voxel on each side).
    [[nodiscard]] glm::dvec3 extentMm() const {
        return glm::dvec3(dims[0], dims[1], dims[2]) * spacingMm;
    }
};

/// Largest number of voxels along one axis that any loader accepts (the Vulkan 3D image limit
/// on the devices we target is 4096; larger sizes are corrupt headers, not CT scans).
inline constexpr int kMaxDimension = 4096;
/// Voxel spacing outside [kMinSpacingMm, kMaxSpacingMm] is treated as a corrupt header.
inline constexpr double kMinSpacingMm = 1e-3;
inline constexpr double kMaxSpacingMm = 100.0;
/// Largest voxel count any loader accepts (1024^3 voxels, 2 GiB of int16): a header asking for
/// more is corrupt or hostile, and is refused before anything is allocated.
inline constexpr std::size_t kMaxVoxelCount = std::size_t{1} << 30;

/// Patient LPS millimetres of a point given in volume millimetres (see Volume).
glm::dvec3 patientFromVolumeMm(const Volume& volume, const glm::dvec3& pointMm);

/// The unit vector, in volume axes, of a direction given in the patient frame (LPS): the
/// patient's anterior is volumeDirectionFromPatient(volume, {0, -1, 0}). directionLps is
/// orthonormal, so its transpose is its inverse.
glm::dvec3 volumeDirectionFromPatient(const Volume& volume, const glm::dvec3& directionLps);

/// Throws VolumeError naming `source` unless dims, spacing, direction and voxel count are sane.
void validateVolume(const Volume& volume, const std::string& source);

/// validateVolume without looking at the voxels (that hu holds one value per voxel): loaders
/// call it on the header's grid before they allocate, so a corrupt header (absurd dims, spacing
/// or direction, more than kMaxVoxelCount voxels) never triggers a huge allocation.
void validateGeometry(const Volume& volume, const std::string& source);

}  // namespace volumes
