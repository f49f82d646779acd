/// @brief The shape error a display's map alone gives a polyp, with nothing rendered: the image
/// of a circle of the polyp's angular radius about its direction (or of the polyp's own outline,
/// from its ground truth), through the map, measured as a view is measured (polyp_shape.h)
/// against the same outline without the map.
///
/// A conformal map keeps shapes in the small; over a polyp's extent its scale changes, which
/// bends a disc into an egg whose second moments differ from a disc's at second order in the
/// disc's size, and near the map's singular points faster. An elongated outline (a sessile polyp
/// seen from the side) loses more: the same change of second moments weighs on its narrow axis,
/// about the square of its aspect more. The prediction measures exactly that term: the outline
/// seen from the map centre, its preimage sampled finely in display directions (each sample's
/// direction, solid angle and hit on the polyp, as a rendered pixel gives them), so polyp-check
/// can compare what it renders with what the map itself costs, and place the eye where that cost
/// stays within a target.
#pragma once

#include <functional>

#include <glm/glm.hpp>

#include "colon/polyp_shape.h"

namespace colon {

/// A display's map: the unit scene direction that a unit display direction shows (F of
/// DESIGN.md; both in one frame).
using SceneFromDisplay = std::function<glm::dvec3(const glm::dvec3&)>;

struct PredictedShape {
    bool isFound = false;                ///< a display direction shows the polyp's centre
    glm::dvec3 displayDirection{0.0};    ///< that direction: where the map shows the polyp
    double displayRadiusRad = 0.0;       ///< the largest angle of the polyp's image from it
    ShapeMeasures view;                  ///< the circle's image through the map
    ShapeMeasures reference;             ///< the circle seen without a map, sampled alike
    double aspectError = 0.0;            ///< |view - reference| / reference, as polyp-check's
    double circularityError = 0.0;
    double gridAngleErrorDeg = 0.0;
};

/// The prediction for `polyp` given in the map's frame about its centre (the map centre at the
/// origin): its own outline as seen from there (colon::firstPolypHit, nothing else in the way),
/// through the map, against the same outline without it. The map is inverted at the polyp's aim
/// point (a search over the sphere, then Newton's method); where no display direction shows it,
/// isFound is false and the measures are empty. The image is sampled on `samplesAcross`^2
/// display directions around it. Throws std::invalid_argument for a polyp at the origin or
/// wider than 30 degrees seen from there, or fewer than 32 samples across.
PredictedShape predictPolypShape(const SceneFromDisplay& sceneFromDisplay, const PolypSurface& polyp,
                                 int samplesAcross = 320);

/// The prediction for a circle: a sphere whose centre lies along the unit scene direction
/// `sceneDirection` from the map centre and whose outline subtends `angularRadiusRad` there (a
/// polyp's angular radius, whatever its kind and however it is turned). Throws
/// std::invalid_argument for a zero direction, a radius outside (0, 30] degrees or fewer than 32
/// samples across.
PredictedShape predictPolypShape(const SceneFromDisplay& sceneFromDisplay, const glm::dvec3& sceneDirection,
                                 double angularRadiusRad, int samplesAcross = 320);

}  // namespace colon
