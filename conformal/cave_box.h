/// @brief The CAVE's box, which of its walls the display lacks, and the point the map is
/// centred on: the geometry both sides of the map are built from.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace conformal {

/// Box faces in Vulkan cube-map order: +X (right), -X (left), +Y (ceiling), -Y (floor),
/// +Z (back), -Z (front).
inline constexpr int kBoxFaceCount = 6;
inline constexpr int kCeilingFace = 2;
constexpr std::uint32_t faceBit(int face) { return 1u << face; }

/// An axis-aligned display box in CAVE space (right-handed, metres, y up), centred at the origin:
/// it spans [-size/2, +size/2] on each axis. `missingFaces` names the walls the display lacks
/// (the 5-wall cabin: the ceiling; the classic CAVE: the ceiling and the back). The conformal map
/// is centred on `mapCentre`, a point strictly inside the box.
struct CaveBox {
    glm::dvec3 size{2.4, 2.4, 2.4};  ///< width (x), height (y), depth (z) in metres
    glm::dvec3 mapCentre{0.0};       ///< centre of the sphere of directions, CAVE space, metres
    std::uint32_t missingFaces = faceBit(kCeilingFace);  ///< bit f set: face f is missing
};

/// The Immersive Cabin: four 2.95 m x 2.21 m walls on a 2.95 m square floor, centred.
CaveBox immersiveCabinBox();

/// "right", "left", "ceiling", "floor", "back" or "front" for faces 0..5.
std::string boxFaceName(int face);
/// The names of the faces in `faces`, comma separated ("ceiling, back").
std::string boxFaceNames(std::uint32_t faces);

bool isFaceMissing(const CaveBox& box, int face);

/// Throws std::invalid_argument unless every size is positive and finite, the map centre lies
/// strictly inside the box, and the directions of the present walls form a disc that the map
/// can open the missing walls onto: some wall is missing and some present, the missing walls
/// are connected and so are the present ones (else the visible directions are an annulus or in
/// pieces), and at least two box corners touch exactly one missing wall (the slit's tips).
void validateCaveBox(const CaveBox& box);

/// Box corners are indexed by bits: 1 for +x, 2 for +y, 4 for +z. Their point in CAVE space.
glm::dvec3 boxCornerPoint(const CaveBox& box, int corner);
/// The three faces that meet at a corner.
std::array<int, 3> facesAtCorner(int corner);
/// How many of the faces at a corner are missing.
int missingFacesAtCorner(const CaveBox& box, int corner);
/// The unit direction from the map centre to a corner.
glm::dvec3 boxCornerDirection(const CaveBox& box, int corner);

/// The corners that touch exactly one missing face: there the visible directions have a reflex
/// corner (the 5-wall cabin's four ceiling corners), and the slit X ends. Ordered by the
/// azimuth arg(x + i z) of their direction in [0, 2 pi), so the cabin's order is that of
/// ceilingCornerDirections.
std::vector<int> slitTipCorners(const CaveBox& box);

/// The corners of the visible directions' boundary: corners touching one or two missing faces
/// (reflex and convex corners), where the map is singular. Increasing corner index.
std::vector<int> boundaryCorners(const CaveBox& box);

/// Unit directions from the map centre to the four ceiling corners, in counter-clockwise order
/// of azimuth arg(x + i z): k = 0 is (+x, +z), 1 is (-x, +z), 2 is (-x, -z), 3 is (+x, -z).
std::array<glm::dvec3, 4> ceilingCornerDirections(const CaveBox& box);

/// The missing face whose closed rectangle the ray from the map centre along `direction` leaves
/// the box through, or -1 when it leaves through a present one.
int missingFaceOfDirection(const CaveBox& box, const glm::dvec3& direction);

/// True when the ray from the map centre along `direction` leaves the box through a closed
/// missing face, i.e. the direction is outside the display domain (Omega5 for the cabin).
bool isMissingDirection(const CaveBox& box, const glm::dvec3& direction);

}  // namespace conformal
