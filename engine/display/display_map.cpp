#include "engine/display/display_map.h"

#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>
#include <stdexcept>

namespace engine {
namespace {

/// A file's header stores the float64 values it was baked with; anything beyond rounding in a
/// hand-written display file means another CAVE.
constexpr double kToleranceM = 1e-9;

bool isSameLength(const glm::dvec3& a, const glm::dvec3& b) {
    return std::abs(a.x - b.x) <= kToleranceM && std::abs(a.y - b.y) <= kToleranceM &&
           std::abs(a.z - b.z) <= kToleranceM;
}

/// Enough digits that two values differing by more than the tolerance print differently.
std::ostringstream preciseStream() {
    std::ostringstream text;
    text << std::setprecision(12);
    return text;
}

std::string boxText(const glm::dvec3& size) {
    std::ostringstream text = preciseStream();
    text << size.x << " x " << size.y << " x " << size.z << " m";
    return text.str();
}

std::string pointText(const glm::dvec3& point) {
    std::ostringstream text = preciseStream();
    text << "(" << point.x << ", " << point.y << ", " << point.z << ") m";
    return text.str();
}

}  // namespace

conformal::BakeSettings bakeSettingsFor(const Display& display, int size) {
    std::set<WallName> walls;
    for (const DisplayWall& wall : display.walls) walls.insert(wall.name);
    if (walls.size() == 6) {
        throw std::invalid_argument("display '" + display.name + "' has no missing wall: there is no map to bake");
    }
    if (display.map == conformal::MapKind::None) {
        throw std::invalid_argument("display '" + display.name +
                                    "' asks for no map (map none): there is no map to bake");
    }
    validateDisplay(display);
    conformal::BakeSettings settings;
    settings.size = size;
    settings.box = caveBoxOf(display);
    settings.kind = display.map;
    return settings;
}

conformal::CubeMap cubeMapFor(const Display& display, int size, const std::string& cubeMapFile,
                              conformal::BakeReport* report) {
    if (cubeMapFile.empty()) return conformal::cachedCubeMap(bakeSettingsFor(display, size), report);
    conformal::BakeSettings settings;
    try {
        settings = bakeSettingsFor(display, size);
    } catch (const std::invalid_argument& error) {
        throw std::invalid_argument("cube map " + cubeMapFile + " cannot be used: " + error.what());
    }

    if (report) *report = conformal::BakeReport{};
    conformal::CubeMap map = conformal::loadCubeMap(cubeMapFile);
    const std::string file = "cube map " + cubeMapFile;
    const std::string theDisplay = "the display '" + display.name + "'";
    if (map.kind != settings.kind) {
        throw std::invalid_argument(file + " holds the " + conformal::mapKindName(map.kind) + " map, " + theDisplay +
                                    " asks for " + conformal::mapKindName(settings.kind));
    }
    if (!isSameLength(map.box.size, settings.box.size)) {
        throw std::invalid_argument(file + " was baked for box " + boxText(map.box.size) + ", " + theDisplay +
                                    " has " + boxText(settings.box.size));
    }
    if (!isSameLength(map.box.mapCentre, settings.box.mapCentre)) {
        throw std::invalid_argument(file + " was baked for map centre " + pointText(map.box.mapCentre) + ", " +
                                    theDisplay + " has its map centre at " + pointText(settings.box.mapCentre));
    }
    if (map.box.missingFaces != settings.box.missingFaces) {
        throw std::invalid_argument(file + " was baked for a display lacking " +
                                    conformal::boxFaceNames(map.box.missingFaces) + ", " + theDisplay + " lacks " +
                                    conformal::boxFaceNames(settings.box.missingFaces));
    }
    return map;
}

}  // namespace engine
