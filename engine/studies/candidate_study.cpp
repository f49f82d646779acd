#include "engine/studies/candidate_study.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

#include "colon/colon_analysis.h"
#include "colon/slicer_files.h"
#include "colon/surface_view.h"
#include "colon/wall_surface.h"
#include "engine/output/png_writer.h"
#include "engine/output/text_file.h"
#include "engine/review/review_sheet.h"
#include "engine/sequence/camera_path.h"
#include "volumes/load_volume.h"

namespace engine {
namespace {

namespace fs = std::filesystem;

nlohmann::json vecJson(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

bool isCandidatePicture(const fs::path& path) {
    const std::string name = path.filename().string();
    return name.rfind("candidate_", 0) == 0 && path.extension() == ".png";
}

std::string pictureName(std::size_t rank) {
    const std::string number = std::to_string(rank + 1);
    return "candidate_" + std::string(number.size() < 2 ? 2 - number.size() : 0, '0') + number + ".png";
}

/// A view down onto the candidate from where its diameter was measured, 2.5 diameters across.
void writePicture(const volumes::Volume& volume, const colon::PolypCandidate& candidate, double isoHu,
                  const fs::path& path) {
    colon::SurfaceViewRequest view;
    view.eyeMm = candidate.viewEyeMm;
    view.lookAtMm = candidate.centreMm;
    view.up = std::abs(candidate.normal.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
    const double distance = glm::length(view.eyeMm - view.lookAtMm);
    view.fovDeg = std::clamp(2.0 * std::atan(1.25 * candidate.diameterMm / distance) * 180.0 / M_PI, 10.0, 120.0);
    view.size = 192;
    view.isoHu = isoHu;
    view.maxDistanceMm = distance + 4.0 * candidate.diameterMm;
    const colon::HitImage image = colon::surfaceView(volume, view);
    writePng(path.string(), image.width, image.height, colon::shadedSurfaceView(image, view.eyeMm), true);
}

nlohmann::json settingsJson(const colon::CandidateSettings& s, double sigmaMm) {
    return {{"iso_hu", s.isoHu},
            {"smoothing_sigma_mm", sigmaMm},
            {"seed_shape_index", s.seedShapeIndex},
            {"grow_shape_index", s.growShapeIndex},
            {"curvedness_per_mm", {s.minCurvedness, s.maxCurvedness}},
            {"min_cap_area_mm2", s.minCapAreaMm2},
            {"max_elongation", s.maxElongation},
            {"min_diameter_mm", s.minDiameterMm},
            {"max_candidates", s.maxCandidates}};
}

/// Every point of the path inside the volume's box (one voxel of slack for the rounding of a
/// file's coordinates): a path from another scan places candidates on frames that are not there.
void requirePathInVolume(const Centreline& centreline, const volumes::Volume& volume, const std::string& pathFile) {
    const glm::dvec3 slack = volume.spacingMm;
    const glm::dvec3 extent = glm::dvec3(volume.dims[0] - 1, volume.dims[1] - 1, volume.dims[2] - 1) * volume.spacingMm;
    for (std::size_t s = 0; s < centreline.segments.size(); ++s) {
        for (std::size_t i = 0; i < centreline.segments[s].size(); ++i) {
            const glm::dvec3& p = centreline.segments[s][i];
            if (glm::all(glm::greaterThanEqual(p, -slack)) && glm::all(glm::lessThanEqual(p, extent + slack))) continue;
            std::ostringstream message;
            message << std::fixed << std::setprecision(1) << pathFile << ": point " << i + 1 << " of segment " << s + 1
                    << " (" << p.x << ", " << p.y << ", " << p.z << " mm) lies outside the volume (0.." << extent.x
                    << ", 0.." << extent.y << ", 0.." << extent.z << " mm)";
            throw std::invalid_argument(message.str());
        }
    }
}

}  // namespace

void prepareCandidateFolder(const std::string& folder, bool force) {
    const fs::path dir(folder);
    if (fs::exists(dir) && !fs::is_directory(dir)) throw std::runtime_error(folder + " is a file, not a folder");
    fs::create_directories(dir);
    std::vector<fs::path> ours = {dir / "candidates.json", dir / "candidates.mrk.json"};
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (isCandidatePicture(entry.path())) ours.push_back(entry.path());
    }
    for (const auto& path : ours) {
        if (!fs::exists(path)) continue;
        if (!force) throw std::runtime_error(path.string() + " exists (use --force to replace it)");
        fs::remove(path);
    }
    const fs::path probe = dir / ".cvc_write_probe";
    {
        std::ofstream out(probe);
        if (!out) throw std::runtime_error("cannot write into " + folder);
    }
    fs::remove(probe);
}

namespace {

/// The settings in range and the output folder ready (prepareCandidateFolder).
void checkCandidateStudy(const CandidateStudySettings& settings) {
    if (!(settings.pathStepMm > 0.0 && settings.pathStepMm <= 1000.0)) {
        throw std::invalid_argument("--path-step must be in (0, 1000] mm");
    }
    if (settings.pictures < 0 || settings.pictures > 100) throw std::invalid_argument("--pictures must be 0..100");
    prepareCandidateFolder(settings.outFolder, settings.force);
}

}  // namespace

CandidateStudyResult runCandidateStudy(const CandidateStudySettings& settings,
                                       const std::function<void(const std::string&)>& say) {
    checkCandidateStudy(settings);  // before the volume loads: a refusal comes at once
    volumes::LoadOptions load;
    if (!settings.rawSpec.empty()) load.raw = volumes::parseRawSpec(settings.rawSpec);
    say("candidates: loading " + settings.volumePath);
    volumes::Volume volume = volumes::loadVolume(settings.volumePath, load);
    return candidateStudyOf(volume, settings, say);
}

CandidateStudyResult candidateStudyOf(volumes::Volume& volume, const CandidateStudySettings& settings,
                                      const std::function<void(const std::string&)>& say) {
    const auto start = std::chrono::steady_clock::now();
    checkCandidateStudy(settings);
    Centreline centreline;  // a path file is read and checked before the analysis's minutes
    if (!settings.pathFile.empty() && settings.pathFile != "auto") {
        centreline = readCentreline(settings.pathFile);
        requirePathInVolume(centreline, volume, settings.pathFile);
    }
    const auto progress = [&say](const std::string& step, int done, int total) {
        say("candidates: colon [" + std::to_string(done) + '/' + std::to_string(total) + "] " + step);
    };
    const colon::ColonAnalysis analysis = colon::analyseColon(volume, colon::ColonSettings{}, progress);
    if (settings.pathFile == "auto") {
        for (const auto& segment : analysis.segments) centreline.segments.push_back(segment.centreline.pointsMm);
    }
    std::vector<glm::dvec3> framePositions;
    if (!centreline.segments.empty()) {
        PathSettings path;
        path.stepMm = settings.pathStepMm;
        for (const auto& pose : posesAlongSegments(centreline, path)) framePositions.push_back(pose.positionMm);
    }

    say("candidates: meshing the colon wall");
    std::vector<uint8_t> isLumen(analysis.labels.hu.size());
    for (std::size_t n = 0; n < isLumen.size(); ++n) isLumen[n] = analysis.labels.hu[n] >= colon::kLabelFirstSegment ? 1 : 0;
    colon::WallSurfaceSettings wallSettings;
    wallSettings.isoHu = settings.candidates.isoHu;
    const colon::WallSurface wall = colon::colonWallSurface(volume, isLumen, wallSettings);

    CandidateStudyResult result;
    result.search = colon::findPolypCandidates(volume, wall, settings.candidates,
                                               [&say](const std::string& step) { say("candidates: " + step); });
    result.frames = static_cast<int>(framePositions.size());
    for (const auto& candidate : result.search.candidates) {
        result.places.push_back(colon::placeOnPath(centreline.segments, candidate.centreMm, framePositions));
    }

    const fs::path folder(settings.outFolder);
    const std::size_t pictures = std::min(result.search.candidates.size(), static_cast<std::size_t>(settings.pictures));
    if (pictures > 0) say("candidates: pictures of the first " + std::to_string(pictures));
    for (std::size_t r = 0; r < pictures; ++r) {
        writePicture(volume, result.search.candidates[r], settings.candidates.isoHu, folder / pictureName(r));
        result.pictures.push_back((folder / pictureName(r)).string());
    }

    std::vector<colon::MarkupsPoint> points;
    nlohmann::json list = nlohmann::json::array();
    for (std::size_t r = 0; r < result.search.candidates.size(); ++r) {
        const auto& c = result.search.candidates[r];
        const auto& place = result.places[r];
        std::ostringstream description;
        description << std::fixed << std::setprecision(1) << c.diameterMm << " mm, score " << std::setprecision(2)
                    << c.score;
        points.push_back({"candidate " + std::to_string(r + 1), description.str(), c.centreMm});
        nlohmann::json entry = {{"rank", r + 1},
                                {"centre_mm", vecJson(c.centreMm)},
                                {"centre_lps_mm", vecJson(volumes::patientFromVolumeMm(volume, c.centreMm))},
                                {"normal", vecJson(c.normal)},
                                {"diameter_mm", c.diameterMm},
                                {"score", c.score},
                                {"shape_index", c.shapeIndex},
                                {"curvedness_per_mm", c.curvedness},
                                {"cap_area_mm2", c.capAreaMm2},
                                {"elongation", c.elongation},
                                {"sphere_centre_mm", vecJson(c.sphereCentreMm)},
                                {"sphere_radius_mm", c.sphereRadiusMm},
                                {"segment", place.segment >= 0 ? nlohmann::json(place.segment + 1) : nlohmann::json()},
                                {"arc_length_mm", place.segment >= 0 ? nlohmann::json(place.arcLengthMm) : nlohmann::json()},
                                {"distance_to_path_mm", place.segment >= 0 ? nlohmann::json(place.distanceMm) : nlohmann::json()},
                                {"nearest_frame", place.nearestFrame >= 0 ? nlohmann::json(place.nearestFrame) : nlohmann::json()},
                                {"picture", r < pictures ? nlohmann::json(pictureName(r)) : nlohmann::json()}};
        list.push_back(entry);
    }
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    nlohmann::json doc = {
        {"volume", fs::absolute(settings.volumePath).string()},
        {"path", {{"source", settings.pathFile.empty() ? "none" : settings.pathFile}, {"step_mm", settings.pathStepMm}, {"frames", result.frames}}},
        {"wall", {{"elements", result.search.wallElements}, {"area_mm2", result.search.wallAreaMm2}}},
        {"settings", settingsJson(settings.candidates, colon::candidateSmoothingMm(settings.candidates, volume))},
        {"counts",
         {{"cap_regions", result.search.capRegions},
          {"dropped_small", result.search.droppedSmall},
          {"dropped_elongated", result.search.droppedElongated},
          {"dropped_unmeasured", result.search.droppedUnmeasured},
          {"dropped_beyond_limit", result.search.droppedBeyondLimit},
          {"candidates", result.search.candidates.size()}}},
        {"candidates", list},
        {"seconds", result.seconds}};
    // The path the places refer to, as colon.json holds one: the file is a path for `cvc render
    // --candidates` and `cvc polyp-check --candidates` too.
    nlohmann::json pathPoints = nlohmann::json::array(), starts = nlohmann::json::array();
    for (const auto& segment : centreline.segments) {
        starts.push_back(pathPoints.size());
        for (const auto& p : segment) pathPoints.push_back(vecJson(p));
    }
    if (!pathPoints.empty()) {
        doc["centreline_mm"] = pathPoints;
        doc["segment_starts"] = starts;
        doc["centreline_order"] = "rectum_to_caecum";
    }
    result.json = doc.dump(2) + "\n";
    writeTextFile(folder / "candidates.mrk.json",
              colon::markupsJson(colon::MarkupsKind::Fiducial, "polyp candidates", points, volume, {1.0, 0.8, 0.0}));
    writeTextFile(folder / "candidates.json", result.json);
    return result;
}

std::vector<ReviewCandidate> reviewCandidatesOf(const std::string& candidatesFile, const std::string& pageFolder,
                                                int frames, double pathStepMm) {
    std::ifstream in(candidatesFile);
    if (!in) throw std::runtime_error(candidatesFile + ": cannot open");
    std::vector<ReviewCandidate> candidates;
    try {
        const nlohmann::json doc = nlohmann::json::parse(in);
        if (pathStepMm > 0.0) {
            const double placedAt = doc.at("path").at("step_mm").get<double>();
            if (std::abs(placedAt - pathStepMm) > 1e-9) {
                std::ostringstream message;
                message << candidatesFile << ": its candidates were placed on frames " << placedAt
                        << " mm apart, this render's are " << pathStepMm
                        << " mm apart (run cvc candidates with the same --path and --path-step)";
                throw std::invalid_argument(message.str());
            }
        }
        const fs::path folder = fs::absolute(fs::path(candidatesFile)).parent_path();
        for (const auto& entry : doc.at("candidates")) {
            ReviewCandidate c;
            c.rank = entry.at("rank").get<int>();
            c.diameterMm = entry.at("diameter_mm").get<double>();
            c.score = entry.at("score").get<double>();
            c.shapeIndex = entry.at("shape_index").get<double>();
            const auto& centre = entry.at("centre_mm");
            c.centreMm = {centre.at(0).get<double>(), centre.at(1).get<double>(), centre.at(2).get<double>()};
            if (pathStepMm > 0.0) {
                const auto& nearest = entry.at("nearest_frame");
                c.frame = nearest.is_number_integer() && nearest.get<int>() < frames ? nearest.get<int>() : -1;
            } else {
                c.frame = static_cast<int>(candidates.size());
            }
            if (entry.contains("picture") && entry["picture"].is_string()) {
                c.picture = fs::relative(folder / entry["picture"].get<std::string>(), fs::absolute(pageFolder)).generic_string();
            }
            candidates.push_back(c);
        }
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(candidatesFile + ": not a candidates.json of cvc candidates (" + e.what() + ")");
    }
    return candidates;
}

void ringCandidatesOnFrame(std::vector<ReviewCandidate>& candidates, int frameIndex, const Display& display,
                           const std::vector<WallImage>& walls) {
    const CrossGeometry cross = crossGeometry(display);
    for (ReviewCandidate& candidate : candidates) {
        if (candidate.frame != frameIndex) continue;
        const double reachMm = std::max(1.0, 0.5 * candidate.diameterMm);
        for (Eye eye : {Eye::Left, Eye::Right}) {
            // The wall with the most pixels on the candidate, and those pixels' sums.
            std::size_t best = 0;
            double bestX = 0.0, bestY = 0.0;
            WallName bestWall = WallName::Front;
            for (const WallImage& wall : walls) {
                const RenderedImage& image = wall.image;
                if (wall.eye != eye || image.hitMm.size() != 4 * static_cast<std::size_t>(image.width) * image.height) continue;
                std::size_t count = 0;
                double sumX = 0.0, sumY = 0.0;
                for (int y = 0; y < image.height; ++y) {
                    for (int x = 0; x < image.width; ++x) {
                        const float* h = &image.hitMm[4 * (static_cast<std::size_t>(y) * image.width + x)];
                        if (!(h[3] > 0.0f)) continue;
                        if (glm::length(glm::dvec3(h[0], h[1], h[2]) - candidate.centreMm) > reachMm) continue;
                        ++count;
                        sumX += x + 0.5;
                        sumY += y + 0.5;
                    }
                }
                if (count > best) {
                    best = count;
                    bestX = sumX;
                    bestY = sumY;
                    bestWall = wall.wall;
                }
            }
            if (best == 0 || !cross.cells.count(bestWall)) continue;
            const CrossCell& cell = cross.cells.at(bestWall);
            const double n = static_cast<double>(best);
            // The ring: the pixels' centre, a radius of their disc's with room around it.
            const SheetRing ring{(cell.x + bestX / n) / cross.width, (cell.y + bestY / n) / cross.height,
                                 (1.5 * std::sqrt(n / M_PI) + 6.0) / cross.width};
            (eye == Eye::Left ? candidate.leftRing : candidate.rightRing) = ring;
        }
    }
}

}  // namespace engine
