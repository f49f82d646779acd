/// @brief 1D transfer functions (HU -> colour and opacity) for composite rendering: presets
/// for colon CT, the table the shader samples, and the opacity table empty-space skipping uses.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "volumes/brick_minmax.h"

namespace engine {

/// Opacities of a transfer function are given for a step of this length.
inline constexpr double kTransferReferenceStepMm = 1.0;

/// A piecewise-linear transfer function: control points sorted by HU; colour is linear RGB,
/// opacity is per reference step (kTransferReferenceStepMm), corrected for the actual step:
/// in the table for a fixed step (correctedForStep), per sample for the adaptive step.
struct TransferFunction {
    struct Point {
        double hu;
        glm::vec3 color;
        float opacity;
    };
    std::string name;
    std::vector<Point> points;
};

/// Names of the presets: "colon-wall" (the mucosa seen from the air-filled lumen, the
/// standard look of CT colonography fly-throughs), "soft-tissue", "bone".
std::vector<std::string> transferFunctionPresetNames();

/// The preset called `name`; throws std::invalid_argument listing the names otherwise.
TransferFunction transferFunctionPreset(const std::string& name);

/// The table uploaded to the device: `entries` RGBA values evenly spaced over
/// [firstHu, lastHu], the first and last covering everything beyond (clamp to edge).
struct TransferTable {
    double firstHu = -1024.0;
    double lastHu = 3071.0;
    std::vector<glm::vec4> rgba;
};

/// Samples `function` into a table; throws std::invalid_argument for unsorted or empty points
/// or opacities outside [0, 1].
TransferTable tabulate(const TransferFunction& function, int entries = 1024);

/// The table with each opacity a corrected to a step of `stepMm`: 1 - (1 - a)^(step / reference),
/// the opacity of that much material, so a march at a fixed step needs no power per sample.
/// Zero stays zero, so empty-space skipping selects the same bricks from either table.
TransferTable correctedForStep(const TransferTable& table, double stepMm);

/// The table's opacities in the form brick selection takes (volumes::bricksForOpacity).
volumes::OpacityTable opacityTableOf(const TransferTable& table);

/// The open HU interval (fromHu, toHu) outside which the table, read with linear filtering and
/// clamped at its ends as the shader reads it, gives zero opacity: the entries next to the first
/// and last visible one, widened by one entry more for the texture unit's rounding of the
/// coordinate. Unbounded (a float's largest magnitude) on a side whose end entry is visible or
/// next to one; fromHu > toHu when no entry is visible.
struct VisibleHuRange {
    double fromHu;
    double toHu;
};
VisibleHuRange visibleHuRangeOf(const TransferTable& table);

}  // namespace engine
