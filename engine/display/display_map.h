/// @brief The cube map of a display: one builder of the bake request, shared by `cvc bake` and
/// `cvc render --display`, and the checks that a baked file fits the display it is used for.
#pragma once

#include <string>

#include "conformal/cube_map_baker.h"
#include "engine/display/display.h"

namespace engine {

/// What a bake of `display`'s map needs: its box (boxSizeM), map centre (mapCentreM) and map
/// kind, with `size` texels per face edge; the mesh and flow keep their defaults. Throws
/// std::invalid_argument for a display that has no map to bake: one with all six walls ("has
/// no missing wall"), or one whose map is none; and for a display validateDisplay refuses.
conformal::BakeSettings bakeSettingsFor(const Display& display, int size);

/// The cube map that bends `display`'s rays. With an empty `cubeMapFile`: the bake of
/// bakeSettingsFor(display, size) from the cache (baked and stored on a miss; see
/// conformal::cachedCubeMap), with `report` filled in. With a file: that file as
/// conformal::loadCubeMap reads it, at the file's own size (`size` is ignored), after checking
/// that it was baked for the display's box, map centre (both to 1e-9 m) and map kind; a
/// mismatch throws std::invalid_argument naming the file, what it holds and what the display
/// asks for. `report` is then reset, as nothing was baked or cached. A display without a map to
/// bake is refused as by bakeSettingsFor, the file named too.
conformal::CubeMap cubeMapFor(const Display& display, int size, const std::string& cubeMapFile,
                              conformal::BakeReport* report = nullptr);

}  // namespace engine
