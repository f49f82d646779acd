#include "engine/sequence/camera_path.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace engine {
namespace {

bool isFinite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// Points no closer than this are merged: they carry no direction.
constexpr double kMinSegmentMm = 1e-6;
/// A path file larger than this is not a centreline.
constexpr std::size_t kMaxPoints = 10'000'000;

/// The JSON document in `in`, or an error naming `path`.
nlohmann::json parseJson(const std::string& path, std::istream& in) {
    try {
        return nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(path + ": not valid JSON (" + e.what() + ")");
    }
}

bool isVec3(const nlohmann::json& value) {
    return value.is_array() && value.size() == 3 && value[0].is_number() && value[1].is_number() && value[2].is_number();
}

glm::dvec3 vec3Of(const nlohmann::json& value) {
    return {value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
}

/// The points of a JSON centreline and where its segments start.
struct RawCentreline {
    std::vector<glm::dvec3> points;
    std::vector<std::size_t> segmentStarts{0};
    bool isCaecumFirst = false;
    std::optional<glm::dvec3> anterior;
};

RawCentreline fromJson(const std::string& path, std::istream& in) {
    const nlohmann::json document = parseJson(path, in);
    if (!document.is_object() || !document.contains("centreline_mm") || !document["centreline_mm"].is_array()) {
        throw std::runtime_error(path + ": no \"centreline_mm\" array (expected a phantom's ground truth)");
    }
    RawCentreline raw;
    for (const auto& point : document["centreline_mm"]) {
        if (!isVec3(point)) {
            throw std::runtime_error(path + ": centreline point " + std::to_string(raw.points.size()) +
                                     " is not three numbers");
        }
        raw.points.push_back(vec3Of(point));
        if (raw.points.size() > kMaxPoints) throw std::runtime_error(path + ": more than 10 million points");
    }
    if (document.contains("segment_starts")) {
        const auto& starts = document["segment_starts"];
        if (!starts.is_array() || starts.empty() || starts.size() > raw.points.size()) {
            throw std::runtime_error(path + ": \"segment_starts\" must be a list of at most one index per point");
        }
        raw.segmentStarts.clear();
        for (const auto& start : starts) {
            if (!start.is_number_unsigned() || start.get<std::size_t>() >= raw.points.size() ||
                (!raw.segmentStarts.empty() && start.get<std::size_t>() <= raw.segmentStarts.back()) ||
                (raw.segmentStarts.empty() && start.get<std::size_t>() != 0)) {
                throw std::runtime_error(path + ": \"segment_starts\" must rise from 0 within the centreline's points");
            }
            raw.segmentStarts.push_back(start.get<std::size_t>());
        }
    }
    if (document.contains("centreline_order")) {
        const auto& order = document["centreline_order"];
        if (order == "caecum_to_rectum") {
            raw.isCaecumFirst = true;
        } else if (order != "rectum_to_caecum") {
            throw std::runtime_error(path + ": \"centreline_order\" must be \"rectum_to_caecum\" or \"caecum_to_rectum\"");
        }
    }
    if (document.contains("anterior")) {
        if (!isVec3(document["anterior"]) || !isFinite(vec3Of(document["anterior"])) ||
            glm::length(vec3Of(document["anterior"])) < 1e-6) {
            throw std::runtime_error(path + ": \"anterior\" must be three finite numbers, not all zero");
        }
        raw.anterior = glm::normalize(vec3Of(document["anterior"]));
    }
    return raw;
}

RawCentreline fromText(const std::string& path, std::istream& in) {
    RawCentreline raw;
    std::vector<glm::dvec3>& points = raw.points;
    std::string line;
    int lineNumber = 0;
    while (std::getline(in, line)) {
        ++lineNumber;
        const std::size_t comment = line.find('#');
        if (comment != std::string::npos && line.compare(comment, 9, "# segment") == 0 && !points.empty() &&
            points.size() != raw.segmentStarts.back()) {
            raw.segmentStarts.push_back(points.size());
        }
        line = line.substr(0, comment);
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream fields(line);
        std::vector<std::string> tokens;
        for (std::string token; fields >> token && tokens.size() < 4;) tokens.push_back(token);
        if (tokens.empty()) continue;  // blank or comment line
        if (tokens.size() != 3) {
            throw std::runtime_error(path + ":" + std::to_string(lineNumber) + ": expected three numbers x y z");
        }
        double xyz[3];
        for (int k = 0; k < 3; ++k) {
            char* end = nullptr;
            xyz[k] = std::strtod(tokens[static_cast<std::size_t>(k)].c_str(), &end);
            if (end == tokens[static_cast<std::size_t>(k)].c_str() || *end != '\0' || !std::isfinite(xyz[k])) {
                throw std::runtime_error(path + ":" + std::to_string(lineNumber) + ": '" +
                                         tokens[static_cast<std::size_t>(k)] + "' is not a finite number");
            }
        }
        points.emplace_back(xyz[0], xyz[1], xyz[2]);
        if (points.size() > kMaxPoints) throw std::runtime_error(path + ": more than 10 million points");
    }
    return raw;
}

/// Carries `up` from one forward direction to the next by the rotation that takes one to the
/// other (the double-reflection method of Wang et al. 2008, in its limit of a single step).
glm::dvec3 transportUp(const glm::dvec3& up, const glm::dvec3& fromForward, const glm::dvec3& toForward) {
    const glm::dvec3 axis = glm::cross(fromForward, toForward);
    const double sinAngle = glm::length(axis);
    const double cosAngle = glm::clamp(glm::dot(fromForward, toForward), -1.0, 1.0);
    glm::dvec3 carried = up;
    if (sinAngle > 1e-12) {
        const glm::dvec3 k = axis / sinAngle;
        carried = up * cosAngle + glm::cross(k, up) * sinAngle + k * glm::dot(k, up) * (1.0 - cosAngle);
    }
    // Re-orthogonalise against the new forward to keep rounding from accumulating.
    carried -= glm::dot(carried, toForward) * toForward;
    return glm::normalize(carried);
}


}  // namespace

const std::vector<glm::dvec3>& nearestSegment(const Centreline& centreline, const glm::dvec3& pointMm) {
    if (centreline.segments.empty()) throw std::invalid_argument("path: no segments");
    std::size_t best = 0;
    double bestDistance = std::numeric_limits<double>::max();
    for (std::size_t s = 0; s < centreline.segments.size(); ++s) {
        for (const glm::dvec3& p : centreline.segments[s]) {
            if (glm::length(p - pointMm) < bestDistance) {
                bestDistance = glm::length(p - pointMm);
                best = s;
            }
        }
    }
    return centreline.segments[best];
}

Centreline readCentreline(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open path file");
    const bool isJson = path.size() >= 5 && path.substr(path.size() - 5) == ".json";
    const RawCentreline raw = isJson ? fromJson(path, in) : fromText(path, in);
    Centreline centreline;
    centreline.anterior = raw.anterior;
    for (std::size_t s = 0; s < raw.segmentStarts.size(); ++s) {
        const std::size_t end = s + 1 < raw.segmentStarts.size() ? raw.segmentStarts[s + 1] : raw.points.size();
        std::vector<glm::dvec3> points;
        for (std::size_t i = raw.segmentStarts[s]; i < end; ++i) {
            if (!isFinite(raw.points[i])) throw std::runtime_error(path + ": point " + std::to_string(i) + " is not finite");
            if (points.empty() || glm::length(raw.points[i] - points.back()) > kMinSegmentMm) points.push_back(raw.points[i]);
        }
        if (points.size() < 2) {
            throw std::runtime_error(path + ": " +
                                     (raw.segmentStarts.size() > 1 ? "segment " + std::to_string(s + 1) + " of a path"
                                                                   : std::string("a path")) +
                                     " needs at least two distinct points");
        }
        centreline.segments.push_back(std::move(points));
    }
    if (raw.isCaecumFirst) {
        std::reverse(centreline.segments.begin(), centreline.segments.end());
        for (auto& segment : centreline.segments) std::reverse(segment.begin(), segment.end());
    }
    return centreline;
}

std::vector<glm::dvec3> readPolyline(const std::string& path) {
    std::vector<glm::dvec3> points;
    for (const auto& segment : readCentreline(path).segments) points.insert(points.end(), segment.begin(), segment.end());
    return points;
}

std::vector<CameraPose> posesAlongSegments(const Centreline& centreline, const PathSettings& settings) {
    std::vector<std::vector<glm::dvec3>> segments = centreline.segments;
    if (settings.direction == Direction::Retrograde) std::reverse(segments.begin(), segments.end());
    std::vector<CameraPose> poses;
    for (const auto& segment : segments) {
        double length = 0.0;
        for (std::size_t i = 1; i < segment.size(); ++i) length += glm::length(segment[i] - segment[i - 1]);
        if (length < settings.stepMm) continue;  // too short to take a step in
        PathSettings part = settings;
        part.maxFrames = settings.maxFrames - static_cast<int>(poses.size());
        std::vector<CameraPose> more = posesAlong(segment, part);
        if (!poses.empty()) {
            // Carry up across the gap as along the path: rotate it from the last view to the next.
            glm::dvec3 up = transportUp(poses.back().up, poses.back().forward, more.front().forward);
            for (std::size_t i = 0; i < more.size(); ++i) {
                if (i > 0) up = transportUp(up, more[i - 1].forward, more[i].forward);
                more[i].up = up;
            }
        }
        poses.insert(poses.end(), more.begin(), more.end());
    }
    if (poses.empty()) throw std::invalid_argument("path: no segment is as long as one step");
    return poses;
}

std::vector<CameraPose> posesAlong(const std::vector<glm::dvec3>& polyline, const PathSettings& settings) {
    if (!(settings.stepMm > 0.0) || !(settings.smoothingMm >= 0.0) || !std::isfinite(settings.stepMm) ||
        !std::isfinite(settings.smoothingMm)) {
        throw std::invalid_argument("path: step must be positive and smoothing non-negative");
    }
    if (polyline.size() < 2) throw std::invalid_argument("path: needs at least two points");
    std::vector<glm::dvec3> points = polyline;
    if (settings.direction == Direction::Retrograde) std::reverse(points.begin(), points.end());

    // Cumulative arc length, and the point at any arc length by linear interpolation.
    std::vector<double> arc(points.size(), 0.0);
    for (std::size_t i = 1; i < points.size(); ++i) arc[i] = arc[i - 1] + glm::length(points[i] - points[i - 1]);
    const double total = arc.back();
    const auto pointAt = [&](double s) {
        s = std::clamp(s, 0.0, total);
        const auto upper = std::upper_bound(arc.begin(), arc.end(), s);
        const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(upper - arc.begin()), points.size() - 1);
        const std::size_t j = i == 0 ? 0 : i - 1;
        const double span = arc[i] - arc[j];
        const double f = span > 0.0 ? (s - arc[j]) / span : 0.0;
        return glm::mix(points[j], points[i], f);
    };
    if (!std::isfinite(total)) throw std::invalid_argument("path: its length overflows (coordinates too large)");
    if (total < settings.stepMm) throw std::invalid_argument("path: shorter than one step");
    const double frameCount = std::floor(total / settings.stepMm) + 1.0;
    if (frameCount > settings.maxFrames) {
        // Printed as a double: a path of absurd length has more frames than any integer type holds.
        std::ostringstream message;
        message << "path: " << std::setprecision(4) << frameCount << " frames exceed the limit of " << settings.maxFrames;
        throw std::invalid_argument(message.str());
    }

    std::vector<CameraPose> poses;
    glm::dvec3 previousForward{0.0};
    for (int frame = 0; frame < static_cast<int>(frameCount); ++frame) {
        const double s = frame * settings.stepMm;
        // The smoothed tangent: the chord across the window, widened near the ends.
        const double half = std::max(settings.smoothingMm, 0.5 * settings.stepMm);
        glm::dvec3 chord = pointAt(s + half) - pointAt(s - half);
        if (glm::length(chord) < kMinSegmentMm) chord = pointAt(s + 1.0) - pointAt(s - 1.0);
        CameraPose pose;
        pose.positionMm = pointAt(s);
        pose.forward = glm::normalize(chord);
        if (frame == 0) {
            glm::dvec3 up = settings.initialUp - glm::dot(settings.initialUp, pose.forward) * pose.forward;
            if (glm::length(up) < 1e-6) {
                // The requested up is along the path: take the axis most orthogonal to it.
                const glm::dvec3 a = std::abs(pose.forward.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
                up = a - glm::dot(a, pose.forward) * pose.forward;
            }
            pose.up = glm::normalize(up);
        } else {
            pose.up = transportUp(poses.back().up, previousForward, pose.forward);
        }
        previousForward = pose.forward;
        poses.push_back(pose);
    }
    return poses;
}

CameraPose poseViewing(const std::vector<glm::dvec3>& polyline, const glm::dvec3& pointMm, double elevationDeg,
                       const PathSettings& settings, double azimuthDeg) {
    if (!(std::abs(azimuthDeg) <= 180.0)) throw std::invalid_argument("azimuth must be in [-180, 180] degrees");
    if (!(elevationDeg > 0.0 && elevationDeg < 180.0)) throw std::invalid_argument("elevation must be in (0, 180) degrees");
    PathSettings fine = settings;
    fine.stepMm = 0.25;
    const std::vector<CameraPose> poses = posesAlong(polyline, fine);
    // Seen at elevation e above the horizon ahead (past 90: over the head, behind), the point
    // lies e from the view direction.
    const double wantedAngle = glm::radians(elevationDeg);
    const auto angleTo = [&](const CameraPose& pose) {
        const glm::dvec3 toPoint = pointMm - pose.positionMm;
        const double length = glm::length(toPoint);
        return length > 0.0 ? std::acos(std::clamp(glm::dot(toPoint / length, pose.forward), -1.0, 1.0)) : 0.0;
    };
    // From the pose nearest to the point, where its angle from the view direction is about 90
    // degrees, walk back along the path (the angle falls) or, for a point behind, on past it (the
    // angle grows); stop where it reaches the wanted one. Poses elsewhere on a winding path may
    // see the point at that angle too, but through walls.
    const auto nearest = std::min_element(poses.begin(), poses.end(), [&](const CameraPose& a, const CameraPose& b) {
        return glm::length(a.positionMm - pointMm) < glm::length(b.positionMm - pointMm);
    });
    auto chosen = nearest;
    if (angleTo(*nearest) >= wantedAngle) {
        while (chosen != poses.begin() && angleTo(*chosen) > wantedAngle) --chosen;
        if (chosen != nearest &&
            std::abs(angleTo(*std::next(chosen)) - wantedAngle) < std::abs(angleTo(*chosen) - wantedAngle)) {
            ++chosen;
        }
    } else {
        while (std::next(chosen) != poses.end() && angleTo(*chosen) < wantedAngle) ++chosen;
        if (chosen != nearest &&
            std::abs(angleTo(*std::prev(chosen)) - wantedAngle) < std::abs(angleTo(*chosen) - wantedAngle)) {
            --chosen;
        }
    }
    CameraPose pose = *chosen;
    const glm::dvec3 toPoint = pointMm - pose.positionMm;
    const glm::dvec3 up = toPoint - glm::dot(toPoint, pose.forward) * pose.forward;
    if (glm::length(up) > 1e-9) {
        // Up toward the point, then turned about the view direction by -azimuth, which puts the
        // point azimuth degrees to the right of up (right = forward x up).
        const glm::dvec3 toward = glm::normalize(up);
        const double a = glm::radians(azimuthDeg);
        pose.up = std::cos(a) * toward - std::sin(a) * glm::cross(pose.forward, toward);
    }
    return pose;
}

namespace {

/// The "centre_mm" of every entry of the list `listName` of a JSON file; `entryName` and
/// `expected` name the entries and the file in errors.
std::vector<glm::dvec3> readListCentres(const std::string& path, const std::string& listName,
                                        const std::string& entryName, const std::string& expected) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open " + expected);
    const nlohmann::json document = parseJson(path, in);
    if (!document.is_object() || !document.contains(listName) || !document[listName].is_array()) {
        throw std::runtime_error(path + ": no \"" + listName + "\" list (expected " + expected + ")");
    }
    std::vector<glm::dvec3> centres;
    for (const auto& entry : document[listName]) {
        if (!entry.is_object() || !entry.contains("centre_mm") || !isVec3(entry["centre_mm"])) {
            throw std::runtime_error(path + ": " + entryName + " " + std::to_string(centres.size()) + " has no centre_mm");
        }
        centres.push_back(vec3Of(entry["centre_mm"]));
    }
    return centres;
}

}  // namespace

std::vector<glm::dvec3> readPolypCentres(const std::string& path) {
    return readListCentres(path, "polyps", "polyp", "a phantom's ground truth");
}

std::vector<glm::dvec3> readCandidateCentres(const std::string& path) {
    auto centres = readListCentres(path, "candidates", "candidate", "cvc candidates' candidates.json");
    if (centres.empty()) throw std::runtime_error(path + ": lists no candidates");
    return centres;
}

CameraPose poseLookingAt(const glm::dvec3& positionMm, const glm::dvec3& lookAtMm, const glm::dvec3& up) {
    CameraPose pose;
    pose.positionMm = positionMm;
    const glm::dvec3 view = lookAtMm - positionMm;
    if (!(glm::length(view) >= 1e-9)) throw std::invalid_argument("the look-at point equals the position");
    pose.forward = glm::normalize(view);
    const glm::dvec3 orthogonal = up - glm::dot(up, pose.forward) * pose.forward;
    if (!(glm::length(orthogonal) >= 1e-9)) throw std::invalid_argument("up is parallel to the view direction");
    pose.up = glm::normalize(orthogonal);
    return pose;
}

std::vector<CameraPose> posesFor(const PoseRequest& request) {
    if (!request.pathFile.empty()) {
        const Centreline centreline = readCentreline(request.pathFile);
        PathSettings settings = request.path;
        if (centreline.anterior) settings.initialUp = *centreline.anterior;
        if (!request.candidatesFile.empty()) {
            std::vector<CameraPose> poses;
            for (const glm::dvec3& centre : readCandidateCentres(request.candidatesFile)) {
                poses.push_back(poseViewing(nearestSegment(centreline, centre), centre, request.polypElevationDeg,
                                            settings, request.polypAzimuthDeg));
            }
            return poses;
        }
        if (request.polyp >= 0) {
            const auto centres = readPolypCentres(request.pathFile);
            if (request.polyp >= static_cast<int>(centres.size())) {
                throw std::invalid_argument("polyp " + std::to_string(request.polyp) + ": " + request.pathFile +
                                            " lists " + std::to_string(centres.size()) + " polyps");
            }
            const glm::dvec3 polyp = centres[static_cast<std::size_t>(request.polyp)];
            return {poseViewing(nearestSegment(centreline, polyp), polyp, request.polypElevationDeg, settings,
                                request.polypAzimuthDeg)};
        }
        auto poses = posesAlongSegments(centreline, settings);
        if (request.maxFrames > 0 && static_cast<int>(poses.size()) > request.maxFrames) {
            poses.resize(static_cast<std::size_t>(request.maxFrames));
        }
        return poses;
    }
    if (!request.positionMm || !request.lookAtMm) {
        throw std::invalid_argument("a display render needs --path, or --position and --look-at");
    }
    return {poseLookingAt(*request.positionMm, *request.lookAtMm, request.up)};
}

}  // namespace engine
