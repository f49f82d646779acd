#include "engine/render/transfer_function.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace engine {

std::vector<std::string> transferFunctionPresetNames() { return {"colon-wall", "soft-tissue", "bone"}; }

TransferFunction transferFunctionPreset(const std::string& name) {
    const glm::vec3 mucosa(0.93f, 0.60f, 0.50f);
    const glm::vec3 tissue(0.80f, 0.45f, 0.38f);
    const glm::vec3 boneColor(0.95f, 0.92f, 0.85f);
    if (name == "colon-wall") {
        // Air is clear; the wall turns opaque within ~150 HU of the air/tissue boundary, so
        // the lumen's surface looks like the mucosa an endoscope shows.
        return {name, {{-1024, mucosa, 0.0f}, {-650, mucosa, 0.0f}, {-500, mucosa, 0.6f}, {-350, tissue, 1.0f},
                       {3071, tissue, 1.0f}}};
    }
    if (name == "soft-tissue") {
        return {name, {{-1024, tissue, 0.0f}, {-200, tissue, 0.0f}, {0, tissue, 0.08f}, {80, tissue, 0.15f},
                       {300, boneColor, 0.5f}, {3071, boneColor, 0.9f}}};
    }
    if (name == "bone") {
        return {name, {{-1024, boneColor, 0.0f}, {150, boneColor, 0.0f}, {400, boneColor, 0.7f}, {3071, boneColor, 1.0f}}};
    }
    std::string names;
    for (const auto& preset : transferFunctionPresetNames()) names += (names.empty() ? "" : ", ") + preset;
    throw std::invalid_argument("unknown transfer function '" + name + "' (presets: " + names + ")");
}

TransferTable tabulate(const TransferFunction& function, int entries) {
    const auto& points = function.points;
    if (points.empty()) throw std::invalid_argument("transfer function '" + function.name + "' has no points");
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!std::isfinite(points[i].hu) || points[i].opacity < 0.0f || points[i].opacity > 1.0f) {
            throw std::invalid_argument("transfer function '" + function.name + "': point " + std::to_string(i) +
                                        " needs a finite HU and an opacity in [0, 1]");
        }
        if (i > 0 && points[i].hu <= points[i - 1].hu) {
            throw std::invalid_argument("transfer function '" + function.name + "': points must increase in HU");
        }
    }
    if (entries < 2 || entries > 65536) throw std::invalid_argument("transfer table size must be 2..65536");
    TransferTable table;
    table.firstHu = points.front().hu;
    table.lastHu = points.size() > 1 ? points.back().hu : points.front().hu + 1.0;
    table.rgba.resize(static_cast<std::size_t>(entries));
    std::size_t segment = 0;
    for (int e = 0; e < entries; ++e) {
        const double hu = table.firstHu + (table.lastHu - table.firstHu) * e / (entries - 1);
        while (segment + 2 < points.size() && hu > points[segment + 1].hu) ++segment;
        const auto& a = points[segment];
        const auto& b = points[std::min(segment + 1, points.size() - 1)];
        const float f = b.hu > a.hu ? static_cast<float>(std::clamp((hu - a.hu) / (b.hu - a.hu), 0.0, 1.0)) : 0.0f;
        table.rgba[static_cast<std::size_t>(e)] = glm::vec4(glm::mix(a.color, b.color, f), a.opacity + f * (b.opacity - a.opacity));
    }
    return table;
}

TransferTable correctedForStep(const TransferTable& table, double stepMm) {
    if (!(stepMm > 0.0) || !std::isfinite(stepMm)) throw std::invalid_argument("a transfer table's step must be positive");
    TransferTable corrected = table;
    const double exponent = stepMm / kTransferReferenceStepMm;
    for (glm::vec4& entry : corrected.rgba) {
        const double clear = std::max(1.0 - static_cast<double>(entry.a), 0.0);
        entry.a = static_cast<float>(1.0 - std::pow(clear, exponent));
    }
    return corrected;
}

VisibleHuRange visibleHuRangeOf(const TransferTable& table) {
    const double unbounded = static_cast<double>(std::numeric_limits<float>::max());
    const auto n = static_cast<long long>(table.rgba.size());
    long long first = -1, last = -1;
    for (long long e = 0; e < n; ++e) {
        if (table.rgba[static_cast<std::size_t>(e)].a > 0.0f) {
            if (first < 0) first = e;
            last = e;
        }
    }
    if (first < 0) return {unbounded, -unbounded};
    // Entry e sits at firstHu + e * bin; a value between entries blends its two neighbours, so
    // opacity can be non-zero only strictly between entries first - 1 and last + 1.
    constexpr long long kMargin = 2;  // that neighbour, and one entry for rounding
    const double binHu = (table.lastHu - table.firstHu) / static_cast<double>(n - 1);
    const double fromHu = first - kMargin <= 0 ? -unbounded : table.firstHu + static_cast<double>(first - kMargin) * binHu;
    const double toHu = last + kMargin >= n - 1 ? unbounded : table.firstHu + static_cast<double>(last + kMargin) * binHu;
    return {fromHu, toHu};
}

volumes::OpacityTable opacityTableOf(const TransferTable& table) {
    volumes::OpacityTable opacity;
    const auto n = static_cast<double>(table.rgba.size());
    // Entry e is the value at firstHu + e * bin; a bin of the opacity table spans one step.
    opacity.binHu = (table.lastHu - table.firstHu) / (n - 1.0);
    opacity.firstHu = table.firstHu - 0.5 * opacity.binHu;
    opacity.opacity.reserve(table.rgba.size());
    for (const glm::vec4& entry : table.rgba) opacity.opacity.push_back(entry.a);
    return opacity;
}

}  // namespace engine
