#include "bench/polyline_study.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "conformal/cave_box.h"
#include "conformal/cube_map.h"
#include "engine/display/display_json.h"
#include "engine/display/display_map.h"

namespace bench {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// The shader's constants (shaders/polyline_warp.glsl).
constexpr double kLadder[] = {4.0, 14.0, 49.0};
constexpr double kNearFactor = 1.2;
constexpr double kTolerancePixels = 0.05;

double distanceToSegment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
    const glm::dvec3 ab = b - a;
    const double f = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
    return glm::length(p - (a + f * ab));
}

double percentile(std::vector<double> values, double fraction) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    return values[static_cast<std::size_t>(fraction * static_cast<double>(values.size() - 1))];
}

}  // namespace

void runPolylineStudy(const PolylineStudyRequest& request) {
    if (request.directions < 100 || request.directions > 1000000) throw std::invalid_argument("--directions must be 100..1000000");
    const engine::Display display = engine::loadDisplay(request.display);
    const conformal::CubeMap map = engine::cubeMapFor(display, request.mapSize, "");
    const conformal::CaveBox box = engine::caveBoxOf(display);
    const auto warp = [&](const glm::dvec3& q) {  // W about the map centre, at the origin here
        const double r = glm::length(q);
        return r < 1e-12 ? q : r * glm::normalize(glm::dvec3(conformal::sampleCubeMapBilinear(map, q / r)));
    };
    // The front wall's pixel angle at its centre, as pixelAngleOf gives it.
    const engine::WallRectangle front = engine::wallRectangle(display, engine::WallName::Front);
    const double pixelAngle = 2.0 * std::atan(0.5 * glm::length(front.widthM) / display.walls.front().width /
                                               glm::length(front.topLeftM + 0.5 * (front.widthM + front.heightM)));
    const double ranges[] = {2.0, 5.0, 15.0, 400.0};
    nlohmann::json out;
    out["display"] = request.display;
    out["pixel_angle_rad"] = pixelAngle;
    out["ladder"] = kLadder;
    out["tolerance_pixels"] = kTolerancePixels;
    for (double scale : request.mmPerMetre) {
        const glm::dvec3 eye = (engine::eyePositionM(display, engine::Eye::Left) - display.mapCentreM) * scale;
        const double tNear = display.nearM * scale, tFar = 400.0;
        const double offset = glm::length(eye);
        std::vector<double> chordWorst[3], polylineWorst[3], pieces;
        for (int i = 0; i < request.directions; ++i) {
            // A Fibonacci sphere; directions toward a missing wall are not displayed.
            const double z = 1.0 - (2.0 * i + 1.0) / request.directions;
            const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
            const double phi = i * kPi * (3.0 - std::sqrt(5.0));
            const glm::dvec3 d(r * std::cos(phi), r * std::sin(phi), z);
            if (conformal::isMissingDirection(box, d)) continue;
            const double scaleHere = conformal::sampleCubeMapBilinear(map, d).w;
            const auto curve = [&](double t) { return warp(eye + t * d); };
            // The polyline as the shader builds it.
            std::vector<double> params{tNear};
            for (double k : kLadder) {
                if (k * offset > kNearFactor * tNear && k * offset < tFar) params.push_back(k * offset);
            }
            params.push_back(tFar);
            std::vector<double> kept{params.front()};
            for (std::size_t k = 1; k + 1 < params.size(); ++k) {
                const double allowed = kTolerancePixels * params[k] * pixelAngle * scaleHere;
                if (distanceToSegment(curve(params[k]), curve(kept.back()), curve(params[k + 1])) > allowed) {
                    kept.push_back(params[k]);
                }
            }
            kept.push_back(params.back());
            pieces.push_back(static_cast<double>(kept.size() - 1));
            double chord[3] = {0, 0, 0}, polyline[3] = {0, 0, 0};
            const glm::dvec3 nearPoint = curve(tNear), farPoint = curve(tFar);
            for (int k = 0; k <= 160; ++k) {
                const double t = 2.0 * std::pow(200.0, k / 160.0);
                const int range = t < ranges[1] ? 0 : t < ranges[2] ? 1 : 2;
                const double footprint = t * pixelAngle * scaleHere;
                const glm::dvec3 p = curve(t);
                std::size_t piece = 0;
                while (piece + 2 < kept.size() && t > kept[piece + 1]) ++piece;
                chord[range] = std::max(chord[range], distanceToSegment(p, nearPoint, farPoint) / footprint);
                polyline[range] = std::max(
                    polyline[range], distanceToSegment(p, curve(kept[piece]), curve(kept[piece + 1])) / footprint);
            }
            for (int range = 0; range < 3; ++range) {
                chordWorst[range].push_back(chord[range]);
                polylineWorst[range].push_back(polyline[range]);
            }
        }
        nlohmann::json& entry = out["scales"][std::to_string(scale)];
        entry["eye_offset_mm"] = offset;
        entry["directions"] = pieces.size();
        entry["mean_pieces"] = [&] {
            double sum = 0.0;
            for (double p : pieces) sum += p;
            return sum / static_cast<double>(std::max<std::size_t>(pieces.size(), 1));
        }();
        for (int range = 0; range < 3; ++range) {
            const std::string name = std::to_string(static_cast<int>(ranges[range])) + "_to_" +
                                     std::to_string(static_cast<int>(ranges[range + 1])) + "_mm";
            for (const auto& [model, worst] : {std::pair{"chord", &chordWorst[range]}, std::pair{"polyline", &polylineWorst[range]}}) {
                entry[name][model] = {{"median", percentile(*worst, 0.5)},
                                      {"p90", percentile(*worst, 0.9)},
                                      {"p99", percentile(*worst, 0.99)},
                                      {"max", percentile(*worst, 1.0)}};
            }
        }
    }
    std::cout << out.dump(2) << '\n';
}

}  // namespace bench
