#include "colon/polyp_truth.h"

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "colon/colon_error.h"

namespace colon {
namespace {

glm::dvec3 vec3Field(const nlohmann::json& polyp, const char* name, const std::string& where) {
    const auto it = polyp.find(name);
    if (it == polyp.end() || !it->is_array() || it->size() != 3 || !(*it)[0].is_number() || !(*it)[1].is_number() ||
        !(*it)[2].is_number()) {
        throw ColonError(where + ": \"" + name + "\" is not three numbers");
    }
    const glm::dvec3 v((*it)[0].get<double>(), (*it)[1].get<double>(), (*it)[2].get<double>());
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) throw ColonError(where + ": \"" + name + "\" is not finite");
    return v;
}

}  // namespace

std::vector<PolypSurface> readPolypTruth(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw ColonError(path + ": cannot open the ground truth");
    nlohmann::json document;
    try {
        document = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        throw ColonError(path + ": not valid JSON (" + e.what() + ")");
    }
    if (!document.is_object() || !document.contains("polyps") || !document["polyps"].is_array()) {
        throw ColonError(path + ": no \"polyps\" list (expected a phantom's or cvc insert-polyp's ground truth)");
    }
    std::vector<PolypSurface> polyps;
    for (const auto& entry : document["polyps"]) {
        const std::string where = path + ": polyp " + std::to_string(polyps.size());
        if (!entry.is_object()) throw ColonError(where + " is not an object");
        PolypSurface polyp;
        // Checked as a string first: nlohmann's value() throws its own type_error for another type.
        const auto kindField = entry.find("kind");
        const std::string kind = kindField != entry.end() && kindField->is_string() ? kindField->get<std::string>() : "";
        if (kind != "sessile" && kind != "pedunculated") throw ColonError(where + ": \"kind\" must be sessile or pedunculated");
        polyp.isSessile = kind == "sessile";
        if (!entry.contains("diameter_mm") || !entry["diameter_mm"].is_number() || !(entry["diameter_mm"].get<double>() > 0.0)) {
            throw ColonError(where + ": \"diameter_mm\" must be a positive number");
        }
        polyp.diameterMm = entry["diameter_mm"].get<double>();
        polyp.centreMm = vec3Field(entry, "centre_mm", where);
        polyp.baseMm = vec3Field(entry, "base_mm", where);
        const glm::dvec3 normal = vec3Field(entry, "base_normal", where);
        if (!(glm::length(normal) > 1e-6)) throw ColonError(where + ": \"base_normal\" is zero");
        polyp.baseNormal = glm::normalize(normal);
        polyps.push_back(polyp);
    }
    return polyps;
}

bool isOnPolyp(const PolypSurface& polyp, const glm::dvec3& pointMm, double toleranceMm) {
    const double radius = 0.5 * polyp.diameterMm;
    if (!(glm::length(pointMm - polyp.centreMm) <= radius + toleranceMm)) return false;
    return !polyp.isSessile || glm::dot(pointMm - polyp.baseMm, polyp.baseNormal) >= -toleranceMm;
}

}  // namespace colon
