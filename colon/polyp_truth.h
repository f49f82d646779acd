/// @brief The polyps of a ground-truth JSON (the phantom's, or `cvc insert-polyp`'s): what the
/// shape checks need to tell a polyp's surface from the wall around it.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace colon {

struct PolypSurface {
    bool isSessile = true;      ///< sessile: the half of a sphere above the wall; else a head on a stalk
    double diameterMm = 0.0;
    glm::dvec3 centreMm{0.0};   ///< sphere centre (sessile: on the wall surface)
    glm::dvec3 baseMm{0.0};     ///< where the polyp meets the wall
    glm::dvec3 baseNormal{0.0}; ///< unit wall normal at the base, into the lumen
};

/// The "polyps" list of a ground-truth JSON file. Throws ColonError naming the file and the
/// polyp for a missing file, a missing or malformed field, or a polyp of non-positive size.
std::vector<PolypSurface> readPolypTruth(const std::string& path);

/// Whether a surface point in volume millimetres lies on the polyp: on its sphere (the head of
/// a pedunculated polyp; the stalk and the wall are not the polyp) within `toleranceMm`, and for
/// a sessile polyp above the wall plane.
bool isOnPolyp(const PolypSurface& polyp, const glm::dvec3& pointMm, double toleranceMm);

}  // namespace colon
