#include "colon/polyp_truth.h"

#include <algorithm>
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

/// The JSON document in `path`; `what` names it when it cannot be opened.
nlohmann::json jsonFile(const std::string& path, const std::string& what) {
    std::ifstream in(path);
    if (!in) throw ColonError(path + ": cannot open " + what);
    try {
        return nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        throw ColonError(path + ": not valid JSON (" + e.what() + ")");
    }
}

}  // namespace

std::vector<PolypSurface> readPolypTruth(const std::string& path) {
    const nlohmann::json document = jsonFile(path, "the ground truth");
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
        if (kind != "sessile" && kind != "pedunculated" && kind != "flat")
            throw ColonError(where + ": \"kind\" must be sessile, pedunculated or flat");
        polyp.isSessile = kind != "pedunculated";
        polyp.isFlat = kind == "flat";
        if (!entry.contains("diameter_mm") || !entry["diameter_mm"].is_number() || !(entry["diameter_mm"].get<double>() > 0.0)) {
            throw ColonError(where + ": \"diameter_mm\" must be a positive number");
        }
        polyp.diameterMm = entry["diameter_mm"].get<double>();
        // Truth written before flat polyps has no sphere radius: its spheres are half the diameter.
        const auto sphereField = entry.find("sphere_radius_mm");
        if (sphereField != entry.end()) {
            if (!sphereField->is_number() || !(sphereField->get<double>() >= 0.5 * polyp.diameterMm) ||
                !std::isfinite(sphereField->get<double>())) {
                throw ColonError(where + ": \"sphere_radius_mm\" must be a number of at least half the diameter");
            }
            polyp.sphereRadiusMm = sphereField->get<double>();
        } else if (polyp.isFlat) {
            throw ColonError(where +
                             ": a flat polyp needs \"sphere_radius_mm\" (its cap's sphere is wider than the base)");
        }
        polyp.centreMm = vec3Field(entry, "centre_mm", where);
        polyp.baseMm = vec3Field(entry, "base_mm", where);
        const glm::dvec3 normal = vec3Field(entry, "base_normal", where);
        if (!(glm::length(normal) > 1e-6)) throw ColonError(where + ": \"base_normal\" is zero");
        polyp.baseNormal = glm::normalize(normal);
        polyps.push_back(polyp);
    }
    return polyps;
}

std::vector<PolypSurface> readCandidatesAsPolyps(const std::string& path) {
    const nlohmann::json document = jsonFile(path, "the candidate list");
    if (!document.is_object() || !document.contains("candidates") || !document["candidates"].is_array() ||
        document["candidates"].empty()) {
        throw ColonError(path + ": no \"candidates\" list, or an empty one (expected cvc candidates' candidates.json)");
    }
    std::vector<PolypSurface> polyps;
    for (const auto& entry : document["candidates"]) {
        const std::string where = path + ": candidate " + std::to_string(polyps.size() + 1);
        if (!entry.is_object()) throw ColonError(where + " is not an object");
        const auto number = [&](const char* name) {
            const auto it = entry.find(name);
            if (it == entry.end() || !it->is_number() || !std::isfinite(it->get<double>())) {
                throw ColonError(where + ": \"" + name + "\" is not a number");
            }
            return it->get<double>();
        };
        PolypSurface polyp;
        polyp.diameterMm = number("diameter_mm");
        if (!(polyp.diameterMm > 0.0)) throw ColonError(where + ": \"diameter_mm\" must be positive");
        const glm::dvec3 apex = vec3Field(entry, "centre_mm", where);
        const glm::dvec3 normal = vec3Field(entry, "normal", where);
        if (!(glm::length(normal) > 1e-6)) throw ColonError(where + ": \"normal\" is zero");
        polyp.baseNormal = glm::normalize(normal);
        const double halfDiameter = 0.5 * polyp.diameterMm;
        const double fitted = entry.contains("sphere_radius_mm") ? number("sphere_radius_mm") : 0.0;
        if (fitted > halfDiameter) {
            // A cap of the fitted sphere, as wide as measured: its base circle lies the cap's
            // height below the apex, the sphere's centre its radius below.
            const double capHeight = fitted - std::sqrt(fitted * fitted - halfDiameter * halfDiameter);
            polyp.sphereRadiusMm = fitted;
            polyp.centreMm = apex - fitted * polyp.baseNormal;
            polyp.baseMm = apex - capHeight * polyp.baseNormal;
        } else {
            polyp.centreMm = polyp.baseMm = apex - halfDiameter * polyp.baseNormal;
        }
        polyp.isSessile = true;
        polyp.isFlat = polyp.sphereRadiusMm > halfDiameter;
        polyps.push_back(polyp);
    }
    return polyps;
}

glm::dvec3 polypAimPointOf(const PolypSurface& polyp) {
    if (!polyp.isSessile) return polyp.centreMm;
    const double capHeight = polyp.sphereRadius() - glm::dot(polyp.baseMm - polyp.centreMm, polyp.baseNormal);
    return polyp.baseMm + 0.5 * capHeight * polyp.baseNormal;
}

bool firstPolypHit(const PolypSurface& polyp, const glm::dvec3& originMm, const glm::dvec3& direction, glm::dvec3& hitMm) {
    const double radius = polyp.sphereRadius();
    const glm::dvec3 toCentre = polyp.centreMm - originMm;
    const double along = glm::dot(toCentre, direction);
    const double missSquared = glm::dot(toCentre, toCentre) - along * along;
    if (along <= 0.0 || missSquared > radius * radius) return false;
    hitMm = originMm + (along - std::sqrt(radius * radius - missSquared)) * direction;
    return !polyp.isSessile || glm::dot(hitMm - polyp.baseMm, polyp.baseNormal) >= 0.0;
}

namespace {
constexpr double kRimShareOfCap = 0.25;
}  // namespace

double hiddenInFrontMarginMm(double toleranceMm) { return std::max(1.0, 2.0 * toleranceMm); }

bool isHiddenInFront(const PolypSurface& polyp, const glm::dvec3& originMm, const glm::dvec3& direction,
                     const glm::dvec3& hitMm, double toleranceMm) {
    glm::dvec3 ownHitMm;
    if (!firstPolypHit(polyp, originMm, direction, ownHitMm)) return false;
    if (polyp.isSessile) {
        // The lowest quarter of the cap is its rim, which a wall curving up around the base
        // hides from grazing rays on every polyp alike; a fold in front hides more than that.
        const double capHeight = polyp.sphereRadius() + glm::dot(polyp.centreMm - polyp.baseMm, polyp.baseNormal);
        if (glm::dot(ownHitMm - polyp.baseMm, polyp.baseNormal) < kRimShareOfCap * capHeight) return false;
    }
    const double ownDistance = glm::dot(ownHitMm - originMm, direction);
    const double hitDistance = glm::dot(hitMm - originMm, direction);
    return hitDistance < ownDistance - hiddenInFrontMarginMm(toleranceMm);
}

bool isOnPolyp(const PolypSurface& polyp, const glm::dvec3& pointMm, double toleranceMm) {
    if (!(glm::length(pointMm - polyp.centreMm) <= polyp.sphereRadius() + toleranceMm)) return false;
    return !polyp.isSessile || glm::dot(pointMm - polyp.baseMm, polyp.baseNormal) >= -toleranceMm;
}

}  // namespace colon
