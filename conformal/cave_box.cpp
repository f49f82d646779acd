/// @brief The CAVE's box: validation of its size, map centre and missing walls, and the
/// directions of its corners.
#include "conformal/cave_box.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

namespace conformal {

namespace {

int axisOfFace(int face) { return face / 2; }
bool isPositiveFace(int face) { return face % 2 == 0; }

/// Faces of different axes share an edge; a face and its opposite do not.
bool areAdjacent(int a, int b) { return axisOfFace(a) != axisOfFace(b); }

/// True when the faces in `faces` (a bit set) form one edge-connected group.
bool isConnected(std::uint32_t faces) {
    if (faces == 0) return true;
    int first = 0;
    while ((faces & faceBit(first)) == 0) ++first;
    std::uint32_t reached = faceBit(first);
    for (bool isGrowing = true; isGrowing;) {
        isGrowing = false;
        for (int a = 0; a < kBoxFaceCount; ++a) {
            if ((reached & faceBit(a)) == 0) continue;
            for (int b = 0; b < kBoxFaceCount; ++b) {
                if ((faces & faceBit(b)) != 0 && (reached & faceBit(b)) == 0 && areAdjacent(a, b)) {
                    reached |= faceBit(b);
                    isGrowing = true;
                }
            }
        }
    }
    return reached == faces;
}

constexpr std::uint32_t kAllFaces = (1u << kBoxFaceCount) - 1;

}  // namespace

CaveBox immersiveCabinBox() {
    CaveBox box;
    box.size = glm::dvec3(2.95, 2.21, 2.95);
    box.mapCentre = glm::dvec3(0.0);
    return box;
}

std::string boxFaceName(int face) {
    static const std::array<const char*, kBoxFaceCount> names = {"right", "left", "ceiling", "floor", "back", "front"};
    return face >= 0 && face < kBoxFaceCount ? names[face] : "?";
}

std::string boxFaceNames(std::uint32_t faces) {
    std::string text;
    for (int face = 0; face < kBoxFaceCount; ++face) {
        if ((faces & faceBit(face)) != 0) text += (text.empty() ? "" : ", ") + boxFaceName(face);
    }
    return text.empty() ? "none" : text;
}

bool isFaceMissing(const CaveBox& box, int face) { return (box.missingFaces & faceBit(face)) != 0; }

void validateCaveBox(const CaveBox& box) {
    for (int axis = 0; axis < 3; ++axis) {
        const double extent = box.size[axis];
        if (!std::isfinite(extent) || extent <= 0.0) {
            throw std::invalid_argument("CAVE box: size along axis " + std::to_string(axis) +
                                        " is " + std::to_string(extent) +
                                        " m; expected a positive finite length");
        }
        const double c = box.mapCentre[axis];
        if (!std::isfinite(c) || std::abs(c) >= 0.5 * extent) {
            throw std::invalid_argument("CAVE box: map centre coordinate " + std::to_string(c) +
                                        " on axis " + std::to_string(axis) +
                                        " is not strictly inside the box");
        }
    }
    const std::uint32_t missing = box.missingFaces;
    const std::uint32_t present = kAllFaces & ~missing;
    if ((missing & ~kAllFaces) != 0) {
        throw std::invalid_argument("CAVE box: missing-face mask " + std::to_string(missing) +
                                    " names faces beyond the six");
    }
    if (missing == 0) throw std::invalid_argument("CAVE box: no wall is missing, so there is nothing to map");
    if (present == 0) throw std::invalid_argument("CAVE box: every wall is missing, so there is nothing to map onto");
    if (!isConnected(missing)) {
        throw std::invalid_argument("CAVE box: the missing walls (" + boxFaceNames(missing) +
                                    ") are not connected, so the present walls' directions are not a disc");
    }
    if (!isConnected(present)) {
        throw std::invalid_argument("CAVE box: the present walls (" + boxFaceNames(present) +
                                    ") are in pieces, so their directions are not a disc");
    }
    if (slitTipCorners(box).size() < 2) {
        throw std::invalid_argument("CAVE box: the present walls (" + boxFaceNames(present) +
                                    ") have fewer than two corners where a missing wall meets two present ones; "
                                    "the map needs them to open the missing walls onto the present ones");
    }
}

glm::dvec3 boxCornerPoint(const CaveBox& box, int corner) {
    const glm::dvec3 half = 0.5 * box.size;
    return {(corner & 1) ? half.x : -half.x, (corner & 2) ? half.y : -half.y, (corner & 4) ? half.z : -half.z};
}

std::array<int, 3> facesAtCorner(int corner) {
    return {(corner & 1) ? 0 : 1, (corner & 2) ? 2 : 3, (corner & 4) ? 4 : 5};
}

int missingFacesAtCorner(const CaveBox& box, int corner) {
    int count = 0;
    for (const int face : facesAtCorner(corner)) count += isFaceMissing(box, face) ? 1 : 0;
    return count;
}

glm::dvec3 boxCornerDirection(const CaveBox& box, int corner) {
    return glm::normalize(boxCornerPoint(box, corner) - box.mapCentre);
}

std::vector<int> slitTipCorners(const CaveBox& box) {
    std::vector<int> tips;
    for (int corner = 0; corner < 8; ++corner) {
        if (missingFacesAtCorner(box, corner) == 1) tips.push_back(corner);
    }
    auto azimuth = [&](int corner) {
        const glm::dvec3 d = boxCornerDirection(box, corner);
        const double a = std::atan2(d.z, d.x);
        return a < 0.0 ? a + 2.0 * std::numbers::pi : a;
    };
    std::stable_sort(tips.begin(), tips.end(), [&](int a, int b) { return azimuth(a) < azimuth(b); });
    return tips;
}

std::vector<int> boundaryCorners(const CaveBox& box) {
    std::vector<int> corners;
    for (int corner = 0; corner < 8; ++corner) {
        const int missing = missingFacesAtCorner(box, corner);
        if (missing == 1 || missing == 2) corners.push_back(corner);
    }
    return corners;
}

std::array<glm::dvec3, 4> ceilingCornerDirections(const CaveBox& box) {
    // (+x, +z), (-x, +z), (-x, -z), (+x, -z) at the ceiling (+y): corner bits 1 | 2 | 4 etc.
    return {boxCornerDirection(box, 1 | 2 | 4), boxCornerDirection(box, 2 | 4), boxCornerDirection(box, 2),
            boxCornerDirection(box, 1 | 2)};
}

int missingFaceOfDirection(const CaveBox& box, const glm::dvec3& direction) {
    const glm::dvec3 half = 0.5 * box.size;
    for (int face = 0; face < kBoxFaceCount; ++face) {
        if (!isFaceMissing(box, face)) continue;
        const int axis = axisOfFace(face);
        const double sign = isPositiveFace(face) ? 1.0 : -1.0;
        if (!(direction[axis] * sign > 0.0)) continue;
        // Where the ray meets the face's plane; it leaves through the face when that point
        // lies within the face's closed rectangle.
        const double t = (sign * half[axis] - box.mapCentre[axis]) / direction[axis];
        const glm::dvec3 hit = box.mapCentre + t * direction;
        const int a = (axis + 1) % 3;
        const int b = (axis + 2) % 3;
        if (std::abs(hit[a]) <= half[a] && std::abs(hit[b]) <= half[b]) return face;
    }
    return -1;
}

bool isMissingDirection(const CaveBox& box, const glm::dvec3& direction) {
    return missingFaceOfDirection(box, direction) >= 0;
}

}  // namespace conformal
