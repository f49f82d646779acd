/// @brief An immersive display as a description: the box of walls in CAVE space, the pixels of
/// each wall, the viewer's eyes, the presets and their validation. No GPU types, so the display
/// JSON reader and its fuzz target can use it alone; display.h places it in a volume.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "conformal/cube_map.h"
#include "engine/render/pinhole_camera.h"

namespace engine {

/// The six faces of the CAVE box (DESIGN.md): front -z, back +z, left -x, right +x,
/// floor -y, ceiling +y.
enum class WallName { Front, Back, Left, Right, Floor, Ceiling };

/// "front", "back", "left", "right", "floor", "ceiling"; and back (throws std::invalid_argument).
std::string wallNameText(WallName wall);
WallName wallNameFromText(const std::string& text);

/// One physical wall: a rectangle of the box as the viewer inside sees it, in CAVE metres.
struct DisplayWall {
    WallName name = WallName::Front;
    int width = 1024;   // pixels
    int height = 1024;
};

/// A partially or fully immersive display. CAVE space: right-handed, metres, y up, the box
/// centred at the origin; the map is centred at `mapCentreM`, by default the box centre (the
/// paper's choice). `map` says which map bends the rays: the conformal map, the linear
/// baseline, or none (a display with every wall, or a render without the map).
struct Display {
    std::string name;
    glm::dvec3 boxSizeM{2.4, 2.4, 2.4};  // width (x), height (y), depth (z)
    std::vector<DisplayWall> walls;
    double eyeSeparationM = 0.065;
    glm::dvec3 headPositionM{0.0};       // the point between the eyes; they lie along CAVE x
    double nearM = 0.05;                 // rays start this far in front of the eye
    conformal::MapKind map = conformal::MapKind::Conformal;
    glm::dvec3 mapCentreM{0.0};          // the centre of the map's sphere of directions
};

/// The presets: "ic5" (the 5-wall Immersive Cabin, no ceiling, 1400x1050 walls and a
/// 1050x1050 floor, conformal map: the default), "ic6" (the cabin with a 1050x1050 ceiling, no
/// map: what the cabin would show with every wall), "cave6" (a 2.4 m cube, all six walls at
/// 1024^2, no map), "cave4" (front, left, right, floor of a 2.4 m cube: two walls missing),
/// "forward" (one 1400x1400 screen filling 90 degrees straight ahead, no map: the usual virtual
/// endoscope). ic5 and cave4 bend their rays through the conformal map.
std::vector<std::string> displayPresetNames();
Display displayPreset(const std::string& name);

/// Throws std::invalid_argument naming the field for a display that cannot be rendered: sizes,
/// pixel counts, a wall listed twice, a head or a map centre outside the box, a map that the
/// walls do not support (a bending map needs a missing wall, and present walls whose directions
/// form a disc: conformal::validateCaveBox says why not; the linear map also needs the floor).
void validateDisplay(const Display& display);

/// The box the map is built for: the display's size and map centre, and the walls it lacks.
conformal::CaveBox caveBoxOf(const Display& display);

/// The rectangle of `wall` in CAVE metres, as ViewRays wants it: top-left corner, full width
/// (left to right) and full height (top to bottom) as seen from inside the box. Walls look
/// like an unfolded cross: the floor's top edge meets the front wall's bottom edge, the
/// ceiling's bottom edge the front wall's top edge.
struct WallRectangle {
    glm::dvec3 topLeftM;
    glm::dvec3 widthM;
    glm::dvec3 heightM;
};
WallRectangle wallRectangle(const Display& display, WallName wall);

/// Resizes every wall of `display` so that `widthPixels` span the box's width, at the same pixel
/// density on every wall (each keeps its own proportions, as the display's own walls do).
void resizeWallsToWidth(Display& display, int widthPixels);

enum class Eye { Left, Centre, Right };
std::string eyeText(Eye eye);

/// Position of `eye` in CAVE metres: the head position shifted by half the eye separation
/// along -x (left) or +x (right).
glm::dvec3 eyePositionM(const Display& display, Eye eye);

}  // namespace engine
