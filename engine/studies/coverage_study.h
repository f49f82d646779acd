/// @brief One row of `cvc coverage`, apart from how its frames are shared over ranks: the scene
/// every row measures (the volume as rendered, the colon's wall, the centreline), a row's poses
/// and job, each frame's sheet, the first sightings of several ranks merged in frame order, the
/// unseen patches located and pictured, the row's JSON and its review page, and --compare's table.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "colon/surface_coverage.h"
#include "colon/wall_surface.h"
#include "engine/sequence/camera_path.h"
#include "engine/studies/coverage_run.h"
#include "engine/studies/patch_views.h"
#include "volumes/load_volume.h"

namespace engine {

enum class CoverageDirections { Antegrade, Retrograde, Both };

/// "antegrade", "retrograde" or "both".
std::string coverageDirectionsText(CoverageDirections directions);

/// One row of a run: a display, its map and the directions flown.
struct CoverageRow {
    std::string name;
    Display display;
    CoverageDirections directions = CoverageDirections::Antegrade;
};

/// What a coverage run was asked for, as far as the rows, their JSON and pages need it.
struct CoverageStudySettings {
    std::string volumePath;
    std::string rawSpec;
    std::string pathFile;  // a centreline file, or "auto": the colon analysis's own
    double pathStepMm = 5.0;
    double smoothingMm = 8.0;
    int maxFrames = 0;     // per direction; 0: every frame
    double mmPerMetre = 10.0;
    WarpMode warpMode = WarpMode::EyeCentred;
    double isoHu = -500.0;
    colon::CoverageSettings coverage;
    double minPatchMm2 = 10.0;
    int patchPictures = 8;
};

/// What the analysis gives every row: the volume as rendered (cleansed where fluid was), the
/// colon's wall and the centreline.
struct CoverageScene {
    volumes::LoadedVolume loaded;
    Centreline centreline;
    colon::WallSurface wall;
};

/// Makes `outFolder` ready for a run: an empty or new folder as it is; one that holds output only
/// with `force`, and then only the names a coverage run writes are removed (frames, rows, the
/// summaries, the patches and the review page). Throws std::runtime_error naming the folder when
/// it is a file, holds output without `force`, or is not writable.
void prepareCoverageFolder(const std::string& outFolder, bool force);

/// Throws std::invalid_argument naming the option for settings out of range: no path, a path
/// step, smoothing, frame count, scale, map face size, iso value, footprint, angle, patch area or
/// picture count outside what a run can use.
void validateCoverageStudySettings(const CoverageStudySettings& settings, int mapSize);

/// The display of a row: a preset or display file, its map replaced unless `map` is empty, its
/// walls resized so that `wallWidth` pixels span the box (0: the display's own); validated.
Display coverageRowDisplay(const std::string& name, const std::string& map, int wallWidth);

/// Loads the volume, finds the colon (cleansing it where fluid was), takes the centreline (the
/// analysis's own for "auto") and meshes the wall at the iso value. `say` gets each step's line.
CoverageScene prepareCoverageScene(const CoverageStudySettings& settings, const std::function<void(const std::string&)>& say);

/// The same for a volume already loaded (settings.volumePath only names it).
CoverageScene coverageSceneOf(volumes::LoadedVolume loaded, const CoverageStudySettings& settings,
                              const std::function<void(const std::string&)>& say);

/// The row's job: its display, the poses along the scene's centreline in its directions, and the
/// settings display renders use (hits refined by bisection).
CoverageJob coverageJobOf(const CoverageStudySettings& settings, const CoverageRow& row, const CoverageScene& scene);

/// Writes the centre eye's walls of one frame as folder/frame_NNNN/sheet.png (unfolded as a cross).
void writeCoverageSheet(const std::filesystem::path& folder, int frameIndex, const Display& display,
                        const std::vector<WallImage>& walls);

/// What one row measured.
struct CoverageRowResult {
    CoverageJob job;                        // every frame of the row
    CoverageRunSummary run;                 // this rank's frames
    std::vector<double> cumulativePercent;  // per frame of the row, in order (every rank's frames)
    double sheetSeconds = 0.0;
    std::vector<colon::UnseenPatch> patches;  // every unseen patch of the minimum area, largest first
    std::vector<PatchView> located;           // the largest, with a pose and a picture
};

/// Replays each frame's first sightings (by the row's frame index) in frame order into a fresh
/// coverage of `surface`: the whole row's coverage, and its curve, the same as one process
/// flying every frame (seen is an OR over views).
colon::SurfaceCoverage mergedCoverage(const colon::WallSurface& surface, const colon::CoverageSettings& settings,
                                      const std::vector<std::vector<uint32_t>>& firstSightingsByFrame,
                                      std::vector<double>& cumulativePercent);

/// The unseen patches, a pose for each of the largest, their pictures in folder/patches/ and the
/// whole wall's picture as folder/coverage.png.
void locateAndPictureUnseen(const CoverageStudySettings& settings, const CoverageScene& scene, Raycaster& raycaster,
                            const colon::SurfaceCoverage& coverage, CoverageRowResult& result,
                            const std::filesystem::path& folder);

/// The row's summary (coverage.json).
nlohmann::json coverageRowJson(const CoverageStudySettings& settings, const CoverageRow& row,
                               const colon::SurfaceCoverage& coverage, const CoverageRowResult& result,
                               const std::string& rendererDescription, int ranks);

/// The row's review page in folder: its frames' sheets, the coverage curve, the patches.
void writeCoverageRowPage(const CoverageStudySettings& settings, const CoverageRow& row, const CoverageScene& scene,
                          const colon::SurfaceCoverage& coverage, const CoverageRowResult& result,
                          const std::string& rendererDescription, const std::filesystem::path& folder);

/// --compare's summary and table: a row's entry from its summary, and the table's header and line.
nlohmann::json coverageCompareEntry(const std::string& rowName, const nlohmann::json& rowSummary);
std::string coverageCompareHeader();
std::string coverageCompareLine(const std::string& rowName, const nlohmann::json& rowSummary);

}  // namespace engine
