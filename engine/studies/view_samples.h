/// @brief The pixels of a rendered image as the viewer sees them: each pixel's direction from
/// the eye (the unbent display direction), the solid angle it covers, its first hit and colour,
/// for the shape measures of colon/polyp_shape.h.
#pragma once

#include <vector>

#include "colon/polyp_shape.h"
#include "engine/render/raycaster.h"
#include "engine/render/view_rays.h"

namespace engine {

/// One sample per pixel of `image` (rendered from `rays`, hits included), row by row. Throws
/// std::invalid_argument when the image does not fit the rays or has no hit positions.
std::vector<colon::ViewSample> viewSamples(const ViewRays& rays, const RenderedImage& image);

/// The same samples appended to `samples`: a caller gathering several walls' samples for many
/// views reuses one vector's memory instead of allocating (and page-faulting in) hundreds of
/// megabytes per view.
void appendViewSamples(const ViewRays& rays, const RenderedImage& image, std::vector<colon::ViewSample>& samples);

}  // namespace engine
