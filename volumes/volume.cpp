#include "volumes/volume.h"

#include <cmath>
#include <sstream>

namespace volumes {

void validateVolume(const Volume& volume, const std::string& source) {
    validateGeometry(volume, source);
    if (volume.hu.size() != volume.voxelCount()) {
        std::ostringstream msg;
        msg << source << ": holds " << volume.hu.size() << " voxels, expected "
            << volume.voxelCount();
        throw VolumeError(msg.str());
    }
}

void validateGeometry(const Volume& volume, const std::string& source) {
    for (int axis = 0; axis < 3; ++axis) {
        const int n = volume.dims[static_cast<std::size_t>(axis)];
        if (n < 1 || n > kMaxDimension) {
            std::ostringstream msg;
            msg << source << ": size along axis " << axis << " is " << n << ", expected 1.."
                << kMaxDimension;
            throw VolumeError(msg.str());
        }
        const double s = volume.spacingMm[axis];
        if (!std::isfinite(s) || s < kMinSpacingMm || s > kMaxSpacingMm) {
            std::ostringstream msg;
            msg << source << ": voxel spacing along axis " << axis << " is " << s
                << " mm, expected " << kMinSpacingMm << ".." << kMaxSpacingMm << " mm";
            throw VolumeError(msg.str());
        }
        if (!std::isfinite(volume.originLps[axis])) {
            throw VolumeError(source + ": origin is not finite");
        }
        const glm::dvec3 column = volume.directionLps[axis];
        const double length = glm::length(column);
        if (!std::isfinite(length) || std::abs(length - 1.0) > 1e-3) {
            std::ostringstream msg;
            msg << source << ": direction of axis " << axis << " has length " << length
                << ", expected a unit vector";
            throw VolumeError(msg.str());
        }
    }
    if (volume.voxelCount() > kMaxVoxelCount) {
        std::ostringstream msg;
        msg << source << ": " << volume.dims[0] << "x" << volume.dims[1] << "x" << volume.dims[2]
            << " voxels exceed the limit of " << kMaxVoxelCount << " voxels";
        throw VolumeError(msg.str());
    }
}

glm::dvec3 patientFromVolumeMm(const Volume& volume, const glm::dvec3& pointMm) {
    return volume.originLps + volume.directionLps * pointMm;
}

glm::dvec3 volumeDirectionFromPatient(const Volume& volume, const glm::dvec3& directionLps) {
    return glm::normalize(glm::transpose(volume.directionLps) * directionLps);
}

}  // namespace volumes
