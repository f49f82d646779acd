// cvc.polyp_check, cvc.coverage and cvc.candidates: the studies of `cvc polyp-check`, `cvc
// coverage` and `cvc candidates` run on a volume of the session, on the same code path as the
// program's (one process is rank 0 of 1), returning what their JSON holds as Python objects; with
// an output folder they also write the program's files there.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "colon/polyp_shape.h"
#include "distribution/coverage_over_ranks.h"
#include "distribution/polyp_check_over_ranks.h"
#include "engine/render/volume_texture.h"
#include "engine/studies/candidate_study.h"
#include "engine/studies/coverage_study.h"
#include "engine/studies/polyp_check_request.h"
#include "python/bindings.h"
#include "python/gpu_session.h"

namespace py = pybind11;

namespace cvc_python {
namespace {

namespace fs = std::filesystem;

py::object pythonOf(const nlohmann::json& json) { return py::module_::import("json").attr("loads")(json.dump()); }

py::object polypCheckOf(SessionVolume& volume, const std::string& truth, const std::optional<std::string>& out,
                        const std::string& display, const std::vector<int>& polyps,
                        const std::vector<std::string>& poses, const std::vector<std::string>& maps,
                        const std::string& warp, int wallWidth, int mapSize, double scale, double angularRadius,
                        bool force) {
    engine::PolypCheckRequest request;
    request.truthPath = truth;
    request.display = display;
    request.wallWidth = wallWidth;
    request.polyps = polyps;
    request.poses = poses;
    request.maps = maps;
    request.warp = warp;
    request.mapSize = mapSize;
    request.mmPerMetre = scale;
    request.angularRadiusDeg = angularRadius;
    if (wallWidth < 0 || wallWidth > 16384) throw std::invalid_argument("wall_width must be 0..16384 pixels");
    engine::PolypCheckJob job = engine::polypCheckJobOf(request);
    job.toleranceMm = colon::polypToleranceMm(volume.volume().spacingMm);
    if (out) engine::requirePolypCheckFolder(*out, force);
    nlohmann::json document;
    {
        py::gil_scoped_release release;
        document = distribution::checkPolypsOverRanks(distribution::mpiSession(), volume.raycaster(), job, mapSize,
                                                      {volume.source(), truth, warp},
                                                      out ? fs::path(*out) / "crops" : fs::path());
        volume.cubeMapKey.clear();  // the check left its own maps on the ray caster
        if (out) engine::writePolypCheckFiles(*out, document);
    }
    return pythonOf(document);
}

engine::CoverageDirections directionsOf(const std::string& name) {
    if (name == "antegrade") return engine::CoverageDirections::Antegrade;
    if (name == "retrograde") return engine::CoverageDirections::Retrograde;
    if (name == "both") return engine::CoverageDirections::Both;
    throw std::invalid_argument("directions must be antegrade, retrograde or both, not " + name);
}

py::object coverageOf(const SessionVolume& volume, const std::string& path, const std::string& out,
                      const std::string& display, const std::string& map, int wallWidth, const std::string& directions,
                      double pathStep, double smoothing, int frames, double scale, const std::string& warp, int mapSize,
                      double iso, double maxFootprint, double maxAngle, double minPatch, int patchPictures, bool force) {
    engine::CoverageStudySettings settings;
    settings.volumePath = volume.source();
    settings.pathFile = path;
    settings.pathStepMm = pathStep;
    settings.smoothingMm = smoothing;
    settings.maxFrames = frames;
    settings.mmPerMetre = scale;
    settings.warpMode = engine::warpModeFromName(warp);
    settings.isoHu = iso;
    settings.coverage.maxFootprintMm2 = maxFootprint;
    settings.coverage.maxViewAngleDeg = maxAngle;
    settings.minPatchMm2 = minPatch;
    settings.patchPictures = patchPictures;
    engine::validateCoverageStudySettings(settings, mapSize);
    if (wallWidth < 0 || wallWidth > 16384) throw std::invalid_argument("wall_width must be 0..16384 pixels");
    engine::Display rowDisplay = engine::coverageRowDisplay(display, map, wallWidth);
    const engine::CoverageRow row{rowDisplay.name, rowDisplay, directionsOf(directions)};
    engine::prepareCoverageFolder(out, force);
    nlohmann::json summary;
    {
        py::gil_scoped_release release;
        // The analysis cleanses tagged fluid in place: the scene renders its own copy, so the
        // caller's volume stays as it was.
        volumes::LoadedVolume copy;
        copy.volume = volume.volume();
        copy.bricks = volume.loaded().bricks;
        const engine::CoverageScene scene = engine::coverageSceneOf(std::move(copy), settings, [](const std::string&) {});
        const std::shared_ptr<engine::GpuContext> context = sharedContext();
        engine::VolumeTexture texture(*context, scene.loaded.volume);
        engine::Raycaster raycaster(*context, scene.loaded.volume, texture, scene.loaded.bricks);
        summary = distribution::coverageRowOverRanks(distribution::mpiSession(), settings, row, scene, raycaster, mapSize,
                                                     context->driverDescription(), out);
    }
    return pythonOf(summary);
}

py::object candidatesOf(const SessionVolume& volume, const std::string& out, const std::string& path, double pathStep,
                        double iso, double minDiameter, int maxCandidates, int pictures, bool force) {
    engine::CandidateStudySettings settings;
    settings.volumePath = volume.source();
    settings.pathFile = path == "none" ? "" : path;
    settings.pathStepMm = pathStep;
    settings.outFolder = out;
    settings.force = force;
    settings.pictures = pictures;
    settings.candidates.isoHu = iso;
    settings.candidates.minDiameterMm = minDiameter;
    settings.candidates.maxCandidates = maxCandidates;
    engine::CandidateStudyResult result;
    {
        py::gil_scoped_release release;
        volumes::Volume copy = volume.volume();  // the analysis cleanses tagged fluid in place: not the caller's
        result = engine::candidateStudyOf(copy, settings, [](const std::string&) {});
    }
    return pythonOf(nlohmann::json::parse(result.json));
}

}  // namespace

void addStudyBindings(py::module_& module) {
    const engine::CoverageStudySettings defaults;
    module.def("polyp_check", &polypCheckOf, py::arg("volume"), py::arg("truth"), py::arg("out") = py::none(),
               py::kw_only(), py::arg("display") = "ic5", py::arg("polyps") = std::vector<int>{},
               py::arg("poses") = std::vector<std::string>{},
               py::arg("maps") = std::vector<std::string>{"conformal", "linear", "none"}, py::arg("warp") = "eye-centred",
               py::arg("wall_width") = 0, py::arg("map_size") = 1024, py::arg("scale") = 10.0,
               py::arg("angular_radius") = 5.0, py::arg("force") = false,
               "The polyp-shape check of `cvc polyp-check` on this volume against a ground truth (a phantom's or "
               "cvc insert-polyp's JSON): a dict of what polyp_check.json holds (plan, results, worst). With `out`, "
               "also writes polyp_check.json, polyp_check.md and crops/ there (an earlier check is replaced only with "
               "force=True). wall_width: the box's width in pixels, every wall at that density (0: the display's own).");
    module.def("coverage", &coverageOf, py::arg("volume"), py::arg("path"), py::arg("out"), py::kw_only(),
               py::arg("display") = "ic5", py::arg("map") = "", py::arg("wall_width") = 0,
               py::arg("directions") = "antegrade", py::arg("path_step") = defaults.pathStepMm,
               py::arg("smoothing") = defaults.smoothingMm, py::arg("frames") = 0, py::arg("scale") = defaults.mmPerMetre, py::arg("warp") = "eye-centred",
               py::arg("map_size") = 1024, py::arg("iso") = defaults.isoHu,
               py::arg("max_footprint") = defaults.coverage.maxFootprintMm2,
               py::arg("max_angle") = defaults.coverage.maxViewAngleDeg, py::arg("min_patch") = defaults.minPatchMm2,
               py::arg("patch_pictures") = defaults.patchPictures, py::arg("force") = false,
               "The surface coverage of `cvc coverage` for one display: flies the path (a centreline file, or 'auto' "
               "for the colon analysis's own), writes the run's folder `out` as the program does (frames' sheets, "
               "coverage.png, patches/, unseen_patches.mrk.json, the review page) and returns what coverage.json "
               "holds. The given volume is not changed.");
    const engine::CandidateStudySettings candidateDefaults;
    module.def("candidates", &candidatesOf, py::arg("volume"), py::arg("out"), py::kw_only(), py::arg("path") = "auto",
               py::arg("path_step") = candidateDefaults.pathStepMm, py::arg("iso") = candidateDefaults.candidates.isoHu,
               py::arg("min_diameter") = candidateDefaults.candidates.minDiameterMm,
               py::arg("max_candidates") = candidateDefaults.candidates.maxCandidates,
               py::arg("pictures") = candidateDefaults.pictures, py::arg("force") = false,
               "The polyp candidates of `cvc candidates` on this volume (no GPU): writes candidates.json, "
               "candidates.mrk.json and the pictures into `out` as the program does (an earlier run is replaced only "
               "with force=True) and returns what candidates.json holds. path: 'auto' (the colon analysis's "
               "centreline), a centreline file, or 'none'. The given volume is not changed.");
}

}  // namespace cvc_python
