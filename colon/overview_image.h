/// @brief The overview picture of `cvc colon`: axial, coronal and sagittal projections of the
/// CT side by side (the mean HU along the projection, like a radiograph), the colon lumen
/// tinted per segment over it and the centreline drawn in yellow, its rectal end marked green
/// and its caecal end red. Panels follow the radiological convention: the patient's right on
/// the image's left; anterior up in the axial panel, superior up in the other two.
#pragma once

#include "colon/colon_analysis.h"
#include "colon/rgba_image.h"
#include "volumes/volume.h"

namespace colon {

/// The overview of `analysis` over `ct` (the volume it was computed from, cleansed or not), panels at most
/// maxPanelPixels on a side.
RgbaImage overviewImage(const volumes::Volume& ct, const ColonAnalysis& analysis, int maxPanelPixels = 400);

}  // namespace colon
