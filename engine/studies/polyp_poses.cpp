#include "engine/studies/polyp_poses.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "conformal/cave_box.h"

namespace engine {
namespace {

constexpr double kPi = 3.14159265358979323846;
const glm::dvec3 kAhead(0.0, 0.0, -1.0);

/// The mean of the directions that leave the box through a missing wall (Fibonacci sphere).
glm::dvec3 missingMeanOf(const conformal::CaveBox& box) {
    constexpr int kSamples = 20000;
    glm::dvec3 sum(0.0);
    for (int i = 0; i < kSamples; ++i) {
        const double z = 1.0 - (2.0 * i + 1.0) / kSamples;
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double phi = i * kPi * (3.0 - std::sqrt(5.0));
        const glm::dvec3 d(r * std::cos(phi), r * std::sin(phi), z);
        if (conformal::isMissingDirection(box, d)) sum += d;
    }
    return sum;
}

/// The face's centre point on the box: +X, -X, +Y, -Y, +Z, -Z.
glm::dvec3 faceOffset(const conformal::CaveBox& box, int face) {
    glm::dvec3 offset(0.0);
    offset[face / 2] = (face % 2 == 0 ? 0.5 : -0.5) * box.size[face / 2];
    return offset;
}

}  // namespace

glm::dvec2 elevationAzimuthDegOf(const glm::dvec3& directionCave) {
    const glm::dvec3 d = glm::normalize(directionCave);
    const double elevation = std::asin(std::clamp(d.y, -1.0, 1.0));
    const double azimuth = std::atan2(d.x, -d.z);
    return glm::dvec2(glm::degrees(elevation), glm::degrees(azimuth));
}

glm::dvec3 caveDirectionOf(double elevationDeg, double azimuthDeg) {
    const double el = glm::radians(elevationDeg), az = glm::radians(azimuthDeg);
    return glm::dvec3(std::cos(el) * std::sin(az), std::sin(el), -std::cos(el) * std::cos(az));
}

std::vector<PolypPose> polypPosesFor(const Display& display) {
    const conformal::CaveBox box = caveBoxOf(display);
    if (conformal::isMissingDirection(box, kAhead)) {
        throw std::invalid_argument("polyp poses: display '" + display.name +
                                    "' lacks its front wall, where the poses start");
    }
    const glm::dvec3 missing = missingMeanOf(box);
    if (!(glm::length(missing) > 0.0)) {
        throw std::invalid_argument("polyp poses: display '" + display.name + "' lacks no wall");
    }
    // The sweep: the great circle from straight ahead toward the missing walls' mean direction.
    glm::dvec3 toward = missing - glm::dot(missing, kAhead) * kAhead;
    toward = glm::length(toward) > 1e-9 * glm::length(missing) ? glm::normalize(toward) : glm::dvec3(0.0, 1.0, 0.0);
    const glm::dvec3 side = glm::cross(kAhead, toward);
    const auto along = [&](double degrees) {
        const double s = glm::radians(degrees);
        return std::cos(s) * kAhead + std::sin(s) * toward;
    };
    double s0 = -1.0, s1 = -1.0;
    for (double s = 0.0; s < 360.0 && s1 < 0.0; s += 0.05) {
        const bool isMissing = conformal::isMissingDirection(box, along(s));
        if (isMissing && s0 < 0.0) s0 = s;
        if (!isMissing && s0 >= 0.0) s1 = s;
    }
    if (s0 < 0.0) throw std::invalid_argument("polyp poses: the sweep of display '" + display.name + "' meets no missing wall");
    if (s1 < 0.0) s1 = 360.0;

    std::vector<PolypPose> poses;
    std::set<std::string> names;
    const auto add = [&](std::string name, const glm::dvec3& direction) {
        while (names.count(name)) name += "'";
        names.insert(name);
        poses.push_back({name, glm::normalize(direction)});
    };
    const auto onMissing = [&](double s, const glm::dvec3& direction, const std::string& suffix) {
        const std::string wall = missingWallOf(display, direction);
        add((wall.empty() ? std::string("sweep") : wall) + "_" + std::to_string(static_cast<int>(std::lround(s))) + suffix,
            direction);
    };
    add("wall", along(std::min(15.0, std::max(0.0, s0 - 15.0))));
    add("edge", along(std::max(0.0, s0 - 9.0)));
    for (double offset : {7.0, 13.0, 23.0}) onMissing(s0 + offset, along(s0 + offset), "");
    for (double fraction : {0.25, 0.5, 0.75}) {
        const double s = s0 + fraction * (s1 - s0);
        onMissing(s, along(s), "");
    }
    const double sideTurn = glm::radians(30.0);
    for (double fraction : {0.5, 0.75}) {
        const double s = s0 + fraction * (s1 - s0);
        onMissing(s, std::cos(sideTurn) * along(s) + std::sin(sideTurn) * side, "_side");
    }
    // The slit tip nearest straight ahead, then 5 degrees on toward the missing walls.
    const std::vector<int> tips = conformal::slitTipCorners(box);
    if (!tips.empty()) {
        const int nearest = *std::max_element(tips.begin(), tips.end(), [&](int a, int b) {
            return glm::dot(conformal::boxCornerDirection(box, a), kAhead) <
                   glm::dot(conformal::boxCornerDirection(box, b), kAhead);
        });
        const glm::dvec3 corner = conformal::boxCornerDirection(box, nearest);
        glm::dvec3 away = missing - glm::dot(missing, corner) * corner;
        if (glm::length(away) > 1e-9) {
            add("corner", corner + std::tan(glm::radians(5.0)) * glm::normalize(away));
        }
    }
    return poses;
}

CameraPose poseSeeing(const CameraPose& base, const glm::dvec3& pointMm, const glm::dvec3& directionCave) {
    const glm::dvec3 toPoint = pointMm - base.positionMm;
    if (!(glm::length(toPoint) > 1e-9)) throw std::invalid_argument("pose: the point is at the position");
    // In the frame (forward, left, up) the point's direction is v1 (CAVE: x right, y up, z back).
    const glm::dvec3 c = glm::normalize(directionCave);
    const glm::dvec3 v1(-c.z, -c.x, c.y);
    glm::dvec3 v2 = glm::dvec3(1, 0, 0) - v1.x * v1;
    if (glm::length(v2) < 1e-9) v2 = glm::dvec3(0, 0, 1) - v1.z * v1;
    v2 = glm::normalize(v2);
    const glm::dvec3 v3 = glm::cross(v1, v2);
    // ... and in volume axes it is d; the frame's forward stays as close to base's as it can.
    const glm::dvec3 d = glm::normalize(toPoint);
    glm::dvec3 g = base.forward - glm::dot(base.forward, d) * d;
    if (glm::length(g) < 1e-9) g = base.up - glm::dot(base.up, d) * d;
    g = glm::normalize(g);
    const glm::dvec3 h = glm::cross(d, g);
    const glm::dmat3 rotation = glm::dmat3(d, g, h) * glm::transpose(glm::dmat3(v1, v2, v3));
    CameraPose pose;
    pose.positionMm = base.positionMm;
    pose.forward = glm::normalize(rotation * glm::dvec3(1, 0, 0));
    pose.up = glm::normalize(rotation * glm::dvec3(0, 0, 1));
    return pose;
}

std::vector<glm::dvec3> singularDirectionsOf(const Display& display) {
    const conformal::CaveBox box = caveBoxOf(display);
    std::vector<glm::dvec3> directions;
    for (int corner : conformal::boundaryCorners(box)) directions.push_back(conformal::boxCornerDirection(box, corner));
    for (int a = 0; a < conformal::kBoxFaceCount; ++a) {
        for (int b = a + 1; b < conformal::kBoxFaceCount; ++b) {
            if (a / 2 == b / 2) continue;  // opposite faces share no edge
            if (conformal::isFaceMissing(box, a) == conformal::isFaceMissing(box, b)) continue;
            const glm::dvec3 midpoint = faceOffset(box, a) + faceOffset(box, b);
            directions.push_back(glm::normalize(midpoint - box.mapCentre));
        }
    }
    return directions;
}

double singularDistanceDeg(const std::vector<glm::dvec3>& singular, const glm::dvec3& directionCave) {
    const glm::dvec3 d = glm::normalize(directionCave);
    double nearest = 180.0;
    for (const glm::dvec3& point : singular) {
        nearest = std::min(nearest, glm::degrees(std::acos(std::clamp(glm::dot(d, point), -1.0, 1.0))));
    }
    return nearest;
}

std::string missingWallOf(const Display& display, const glm::dvec3& directionCave) {
    const int face = conformal::missingFaceOfDirection(caveBoxOf(display), glm::normalize(directionCave));
    return face < 0 ? std::string() : conformal::boxFaceName(face);
}

std::vector<PolypPose> polypPosesNamed(const Display& display, const std::vector<std::string>& names) {
    const std::vector<PolypPose> all = polypPosesFor(display);
    if (names.empty()) return all;
    for (const std::string& name : names) {
        if (std::none_of(all.begin(), all.end(), [&](const PolypPose& pose) { return pose.name == name; })) {
            std::string known;
            for (const auto& pose : all) known += (known.empty() ? "" : ", ") + pose.name;
            throw std::invalid_argument("--poses: display '" + display.name + "' has no pose '" + name + "' (it has " +
                                        known + ")");
        }
    }
    std::vector<PolypPose> chosen;
    for (const auto& pose : all) {
        if (std::find(names.begin(), names.end(), pose.name) != names.end()) chosen.push_back(pose);
    }
    return chosen;
}

}  // namespace engine
