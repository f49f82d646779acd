/// @brief The picture of a coverage result on the colon: the wall surface seen from the
/// patient's front and from the patient's left, lit, the wall a fly-through showed in pale
/// tissue colour and what it never showed in red, drawn over everything (dark red where it lies
/// behind the wall in front), the largest unseen patches ringed in yellow. The anterior view
/// follows the radiological convention: the patient's right on the image's left, head up.
#pragma once

#include <vector>

#include "colon/rgba_image.h"
#include "colon/surface_coverage.h"
#include "volumes/volume.h"

namespace colon {

/// `volume` gives the patient's orientation (its directionLps); `ringed` the patches to ring.
RgbaImage coverageImage(const volumes::Volume& volume, const SurfaceCoverage& coverage,
                        const std::vector<UnseenPatch>& ringed, int panelPixels = 420);

}  // namespace colon
