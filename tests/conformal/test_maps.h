/// @brief Small maps shared by the conformal tests, built once per test process.
#pragma once

#include "conformal/conformal_map.h"

namespace conformal::testing {

/// The conformal map of the 2.4 m cube at a small mesh resolution (about a second).
inline const ConformalMap& cubeMap() {
    static const ConformalMap map([] {
        ConformalMapSettings settings;
        settings.mesh.resolution = 64;
        return settings;
    }());
    return map;
}

/// The same for the Immersive Cabin (not a cube: 2.95 x 2.21 x 2.95 m).
inline const ConformalMap& cabinMap() {
    static const ConformalMap map([] {
        ConformalMapSettings settings;
        settings.box = immersiveCabinBox();
        settings.mesh.resolution = 64;
        return settings;
    }());
    return map;
}

/// The classic 4-wall CAVE: the 2.4 m cube lacking the ceiling and the back (+z).
inline CaveBox cave4Box() {
    CaveBox box;
    box.missingFaces = faceBit(kCeilingFace) | faceBit(4);
    return box;
}

/// The conformal map of cave4 at the cube's resolution.
inline const ConformalMap& cave4Map() {
    static const ConformalMap map([] {
        ConformalMapSettings settings;
        settings.box = cave4Box();
        settings.mesh.resolution = 64;
        return settings;
    }());
    return map;
}

}  // namespace conformal::testing
