/// @brief Display descriptions: wall names, presets, validation, wall rectangles and eyes.
#include "engine/display/display_description.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "conformal/cave_box.h"

namespace engine {
namespace {

[[noreturn]] void invalid(const Display& display, const std::string& problem) {
    throw std::invalid_argument("display '" + display.name + "': " + problem);
}

bool isFinite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

std::string wallNameText(WallName wall) {
    switch (wall) {
        case WallName::Front: return "front";
        case WallName::Back: return "back";
        case WallName::Left: return "left";
        case WallName::Right: return "right";
        case WallName::Floor: return "floor";
        case WallName::Ceiling: return "ceiling";
    }
    return "?";
}

WallName wallNameFromText(const std::string& text) {
    for (WallName wall : {WallName::Front, WallName::Back, WallName::Left, WallName::Right, WallName::Floor,
                          WallName::Ceiling}) {
        if (wallNameText(wall) == text) return wall;
    }
    throw std::invalid_argument("unknown wall '" + text + "' (front, back, left, right, floor, ceiling)");
}

std::vector<std::string> displayPresetNames() { return {"ic5", "ic6", "cave6", "cave4", "forward"}; }

Display displayPreset(const std::string& name) {
    Display display;
    display.name = name;
    if (name == "ic5") {
        // The Immersive Cabin: its box is defined once, beside the map that is baked for it.
        const conformal::CaveBox cabin = conformal::immersiveCabinBox();
        display.boxSizeM = cabin.size;
        display.mapCentreM = cabin.mapCentre;
        display.walls = {{WallName::Front, 1400, 1050}, {WallName::Back, 1400, 1050}, {WallName::Left, 1400, 1050},
                         {WallName::Right, 1400, 1050}, {WallName::Floor, 1050, 1050}};
        display.map = conformal::MapKind::Conformal;
    } else if (name == "ic6") {
        // The cabin's box with its ceiling: the upper bound of what the cabin could show. The
        // ceiling has the floor's pixel size, so every wall keeps ic5's pixel density.
        display = displayPreset("ic5");
        display.name = name;
        display.walls.push_back({WallName::Ceiling, 1050, 1050});
        display.map = conformal::MapKind::None;
    } else if (name == "forward") {
        // The usual virtual endoscope: one screen straight ahead, 90 degrees across both ways
        // (the front wall of a cube seen from its centre), at ic5's front-wall pixel density.
        const double side = conformal::immersiveCabinBox().size.x;
        display.boxSizeM = glm::dvec3(side);
        display.walls = {{WallName::Front, 1400, 1400}};
        display.map = conformal::MapKind::None;
    } else if (name == "cave6") {
        display.boxSizeM = glm::dvec3(2.4);
        for (WallName wall : {WallName::Front, WallName::Back, WallName::Left, WallName::Right, WallName::Floor,
                              WallName::Ceiling}) {
            display.walls.push_back({wall, 1024, 1024});
        }
        display.map = conformal::MapKind::None;
    } else if (name == "cave4") {
        display.boxSizeM = glm::dvec3(2.4);
        display.walls = {{WallName::Front, 1024, 1024}, {WallName::Left, 1024, 1024}, {WallName::Right, 1024, 1024},
                         {WallName::Floor, 1024, 1024}};
        display.map = conformal::MapKind::Conformal;
    } else {
        std::string names;
        for (const auto& preset : displayPresetNames()) names += (names.empty() ? "" : ", ") + preset;
        throw std::invalid_argument("unknown display '" + name + "' (presets: " + names + ")");
    }
    return display;
}

void validateDisplay(const Display& display) {
    const glm::dvec3 size = display.boxSizeM;
    if (!isFinite(size) || size.x < 0.1 || size.y < 0.1 || size.z < 0.1 || size.x > 100.0 || size.y > 100.0 ||
        size.z > 100.0) {
        invalid(display, "box size must be 0.1..100 m on each axis");
    }
    if (display.walls.empty()) invalid(display, "lists no walls");
    std::set<WallName> seen;
    for (const DisplayWall& wall : display.walls) {
        if (!seen.insert(wall.name).second) invalid(display, "wall '" + wallNameText(wall.name) + "' is listed twice");
        if (wall.width < 1 || wall.height < 1 || wall.width > kMaxImageSide || wall.height > kMaxImageSide) {
            invalid(display, "wall '" + wallNameText(wall.name) + "' must be 1.." + std::to_string(kMaxImageSide) +
                                 " pixels on each side");
        }
    }
    if (!(display.eyeSeparationM >= 0.0 && display.eyeSeparationM <= 0.5)) {
        invalid(display, "eye separation must be 0..0.5 m");
    }
    if (!(display.nearM > 0.0 && display.nearM < 0.5 * std::min({size.x, size.y, size.z}))) {
        invalid(display, "near plane must be positive and inside the box");
    }
    const glm::dvec3 half = 0.5 * size;
    for (Eye eye : {Eye::Left, Eye::Right}) {
        const glm::dvec3 p = eyePositionM(display, eye);
        if (!isFinite(p) || glm::any(glm::greaterThanEqual(glm::abs(p), half))) {
            invalid(display, "the " + eyeText(eye) + " eye lies outside the box");
        }
    }
    const glm::dvec3 centre = display.mapCentreM;
    if (!isFinite(centre) || glm::any(glm::greaterThanEqual(glm::abs(centre), half))) {
        invalid(display, "map centre (map_centre_m) must lie strictly inside the box");
    }
    if (display.map != conformal::MapKind::None) {
        if (seen.size() == 6) invalid(display, "a bending map is for a display that lacks a wall; use map none");
        const conformal::CaveBox box = caveBoxOf(display);
        try {
            conformal::validateCaveBox(box);
        } catch (const std::invalid_argument& error) {
            invalid(display, std::string("the map cannot be built for its walls (") + error.what() +
                                 "); use map none to render its walls unbent");
        }
        if (display.map == conformal::MapKind::Linear && conformal::isFaceMissing(box, 3)) {
            invalid(display, "the linear map scales angles from the nadir and needs the floor; use map conformal");
        }
    }
}

conformal::CaveBox caveBoxOf(const Display& display) {
    conformal::CaveBox box;
    box.size = display.boxSizeM;
    box.mapCentre = display.mapCentreM;
    // Box faces in Vulkan order: right (+x), left, ceiling (+y), floor, back (+z), front.
    const WallName faceWalls[conformal::kBoxFaceCount] = {WallName::Right, WallName::Left, WallName::Ceiling,
                                                          WallName::Floor, WallName::Back, WallName::Front};
    box.missingFaces = 0;
    for (int face = 0; face < conformal::kBoxFaceCount; ++face) {
        const bool isPresent = std::any_of(display.walls.begin(), display.walls.end(),
                                           [&](const DisplayWall& wall) { return wall.name == faceWalls[face]; });
        if (!isPresent) box.missingFaces |= conformal::faceBit(face);
    }
    return box;
}

WallRectangle wallRectangle(const Display& display, WallName wall) {
    const glm::dvec3 h = 0.5 * display.boxSizeM;
    const glm::dvec3 size = display.boxSizeM;
    switch (wall) {
        case WallName::Front: return {{-h.x, h.y, -h.z}, {size.x, 0, 0}, {0, -size.y, 0}};
        case WallName::Back: return {{h.x, h.y, h.z}, {-size.x, 0, 0}, {0, -size.y, 0}};
        case WallName::Left: return {{-h.x, h.y, h.z}, {0, 0, -size.z}, {0, -size.y, 0}};
        case WallName::Right: return {{h.x, h.y, -h.z}, {0, 0, size.z}, {0, -size.y, 0}};
        case WallName::Floor: return {{-h.x, -h.y, -h.z}, {size.x, 0, 0}, {0, 0, size.z}};
        case WallName::Ceiling: return {{-h.x, h.y, h.z}, {size.x, 0, 0}, {0, 0, -size.z}};
    }
    throw std::logic_error("unknown wall");
}

void resizeWallsToWidth(Display& display, int widthPixels) {
    const double perMetre = widthPixels / display.boxSizeM.x;
    for (DisplayWall& wall : display.walls) {
        const WallRectangle rect = wallRectangle(display, wall.name);
        wall.width = std::max(1, static_cast<int>(std::lround(glm::length(rect.widthM) * perMetre)));
        wall.height = std::max(1, static_cast<int>(std::lround(glm::length(rect.heightM) * perMetre)));
    }
}

std::string eyeText(Eye eye) {
    switch (eye) {
        case Eye::Left: return "left";
        case Eye::Centre: return "centre";
        case Eye::Right: return "right";
    }
    return "?";
}

glm::dvec3 eyePositionM(const Display& display, Eye eye) {
    const double offset = eye == Eye::Left ? -0.5 : eye == Eye::Right ? 0.5 : 0.0;
    return display.headPositionM + glm::dvec3(offset * display.eyeSeparationM, 0.0, 0.0);
}

}  // namespace engine
