/// @brief conformal_measure: the measurements behind docs/conformal.md (not a test; prints
/// tables and writes data for scripts/bench/plot_conformal.py).
///   conformal_measure phi6 RES...                 phi6 against the closed form, per metric
///   conformal_measure accuracy N RES REF_RES BOX   the baked map against the estimated true F
///   conformal_measure timing N RES                 map + bake time, cached load time
///   conformal_measure images RES OUT_DIR           equirectangular data for the pictures
///   conformal_measure display N RES REF_RES BOX    any display: distortion, G o F, convergence
/// BOX is "cube" or "cabin" (both lacking the ceiling) or "cave4" (the 2.4 m cube lacking the
/// ceiling and the back).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "conformal/conformal_map.h"
#include "conformal/cube_map_baker.h"
#include "conformal/distortion.h"
#include "conformal/linear_map.h"
#include "conformal/scene_disk_closed_form.h"

using namespace conformal;
using Complex = std::complex<double>;

namespace {

constexpr double kDegrees = 180.0 / std::numbers::pi;

double seconds(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

double percentile(std::vector<double> values, double fraction) {
    if (values.empty()) return NAN;
    const std::size_t k = std::min(values.size() - 1, static_cast<std::size_t>(fraction * values.size()));
    std::nth_element(values.begin(), values.begin() + k, values.end());
    return values[k];
}

CaveBox boxNamed(const std::string& name) {
    if (name == "cabin") return immersiveCabinBox();
    CaveBox box;
    if (name == "cave4") box.missingFaces = faceBit(kCeilingFace) | faceBit(4);
    return box;
}

struct VertexError {
    double mean = 0.0;
    double p99 = 0.0;
    double max = 0.0;
};

VertexError sceneDiskError(const ConformalMap& map) {
    std::vector<double> errors;
    const SphereMesh& mesh = map.sceneMesh();
    for (std::size_t v = 0; v < mesh.mesh.positions.size(); ++v) {
        if (mesh.slitSector[v] >= 0) continue;
        const Complex exact = sceneDiskFromDirectionClosedForm(map.settings().box, mesh.mesh.positions[v]);
        errors.push_back(std::abs(map.sceneDisk()[v] - exact));
    }
    VertexError e;
    for (const double x : errors) e.mean += x;
    e.mean /= errors.size();
    e.p99 = percentile(errors, 0.99);
    e.max = percentile(errors, 1.0);
    return e;
}

int runPhi6(const std::vector<int>& resolutions) {
    std::printf("| metric | extrapolated | resolution | vertices | flow s | mean error | order | p99 error | max error |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|\n");
    for (const auto metric : {DiscreteMetric::VertexScaling, DiscreteMetric::CirclePacking}) {
        for (const bool isExtrapolated : {false, true}) {
            double previous = NAN;
            for (const int resolution : resolutions) {
                ConformalMapSettings settings;
                settings.mesh.resolution = resolution;
                settings.flow.metric = metric;
                settings.isExtrapolated = isExtrapolated;
                const auto start = std::chrono::steady_clock::now();
                const ConformalMap map(settings);
                const double time = seconds(start);
                const VertexError e = sceneDiskError(map);
                const double order = std::log2(previous / e.mean);
                std::printf("| %s | %s | %d | %zu | %.2f | %.2e | %s | %.2e | %.2e |\n",
                            metric == DiscreteMetric::VertexScaling ? "vertex scaling" : "circle packing",
                            isExtrapolated ? "yes" : "no", resolution, map.sceneMesh().mesh.positions.size(), time,
                            e.mean, std::isfinite(order) ? std::to_string(order).substr(0, 4).c_str() : "-", e.p99,
                            e.max);
                std::fflush(stdout);
                previous = e.mean;
            }
        }
    }
    return 0;
}

/// The estimated true F: the closed-form phi6^-1 after a finely meshed, extrapolated phi5.
class ReferenceMap final : public DirectionMap {
public:
    explicit ReferenceMap(const ConformalMap& fine) : mFine(fine) {}
    glm::dvec3 sceneFromDisplay(const glm::dvec3& d) const override {
        if (isMissingDirection(mFine.settings().box, d)) return mFine.sceneFromDisplay(d);
        return directionFromSceneDiskClosedForm(mFine.settings().box, mFine.diskFromDisplay(d));
    }
    glm::dvec3 displayFromScene(const glm::dvec3& s) const override { return mFine.displayFromScene(s); }

private:
    const ConformalMap& mFine;
};

int runAccuracy(int size, int resolution, int referenceResolution, const std::string& boxName) {
    const CaveBox box = boxNamed(boxName);
    ConformalMapSettings settings;
    settings.box = box;
    settings.mesh.resolution = resolution;
    auto start = std::chrono::steady_clock::now();
    const ConformalMap map(settings);
    const double mapTime = seconds(start);
    settings.mesh.resolution = referenceResolution;
    start = std::chrono::steady_clock::now();
    const ConformalMap fine(settings);
    const double fineTime = seconds(start);
    settings.mesh.resolution = referenceResolution * 3 / 4;
    const ConformalMap second(settings);
    const ReferenceMap reference(fine);
    const ReferenceMap secondReference(second);
    std::printf("box %s: map res %d built in %.2f s; reference res %d in %.2f s\n", boxName.c_str(), resolution,
                mapTime, referenceResolution, fineTime);

    const CubeMap baked = bakeCubeMap(map, box, MapKind::Conformal, size);
    const CubeMap bakedReference = bakeCubeMap(reference, box, MapKind::Conformal, size);

    // The eight singular points on the boundary of Omega5: the corners, and where the zenith's
    // copies land (the preimages of the disk points between the corners).
    std::vector<glm::dvec3> singular;
    for (const auto& corner : ceilingCornerDirections(box)) singular.push_back(corner);
    for (int k = 0; k < 4; ++k) {
        singular.push_back(fine.displayFromDisk(std::polar(1.0 - 1e-12, std::numbers::pi / 4 + k * std::numbers::pi / 2)));
    }
    std::mt19937 random(11);
    std::normal_distribution<double> normal;
    std::vector<double> farMesh, farBaked, nearBaked, nearTrueBilinear, referenceSpread, allBaked;
    std::vector<double> inverseError;
    for (int k = 0; k < 400000; ++k) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(normal(random), normal(random), normal(random)));
        if (isMissingDirection(box, d)) continue;
        const glm::dvec3 exact = reference.sceneFromDisplay(d);
        const double nearestSingular = [&] {
            double a = 10.0;
            for (const auto& p : singular) a = std::min(a, angleBetween(d, p));
            return a;
        }();
        const double bakedError = angleBetween(glm::normalize(glm::dvec3(sampleCubeMapBilinear(baked, d))), exact);
        allBaked.push_back(bakedError);
        if (nearestSingular > 3.0 / kDegrees) {
            farBaked.push_back(bakedError);
            farMesh.push_back(angleBetween(map.sceneFromDisplay(d), exact));
            referenceSpread.push_back(angleBetween(secondReference.sceneFromDisplay(d), exact));
            if (k % 8 == 0) inverseError.push_back(angleBetween(map.displayFromScene(map.sceneFromDisplay(d)), d));
        } else {
            nearBaked.push_back(bakedError);
            nearTrueBilinear.push_back(
                angleBetween(glm::normalize(glm::dvec3(sampleCubeMapBilinear(bakedReference, d))), exact));
        }
    }
    auto row = [](const char* name, const std::vector<double>& e) {
        std::printf("| %s | %zu | %.2e | %.2e | %.2e |\n", name, e.size(), percentile(e, 0.5) * kDegrees,
                    percentile(e, 0.99) * kDegrees, percentile(e, 1.0) * kDegrees);
    };
    std::printf("| angular error (degrees) | directions | median | p99 | max |\n|---|---|---|---|---|\n");
    row("baked map, bilinear, all of Omega5", allBaked);
    row("baked map, bilinear, > 3 deg from singular points", farBaked);
    row("map itself (no cube map), > 3 deg", farMesh);
    row("reference at 3/4 resolution vs reference, > 3 deg", referenceSpread);
    row("baked map, bilinear, < 3 deg from singular points", nearBaked);
    row("true F baked at the same N, bilinear, < 3 deg", nearTrueBilinear);
    row("G o F - identity (map itself), > 3 deg", inverseError);

    const DistortionStatistics stats = distortionStatistics(baked, 1.0);
    const DistortionStatistics walls = distortionStatistics(baked, 5.0);
    const CubeMap linear = bakeCubeMap(LinearMap(box), box, MapKind::Linear, size);
    const DistortionStatistics linearStats = distortionStatistics(linear, 1.0);
    std::printf("\n| K = sigma_max / sigma_min | texels | mean K - 1 | p99 K - 1 | max K | folded texels |\n");
    std::printf("|---|---|---|---|---|---|\n");
    auto krow = [](const char* name, const DistortionStatistics& s) {
        std::printf("| %s | %ld | %.2e | %.2e | %.3f | %ld |\n", name, s.texelCount, s.meanK - 1.0, s.p99K - 1.0,
                    s.maxK, s.foldedTexels);
    };
    krow("conformal, 1 deg around corners left out", stats);
    krow("conformal, 5 deg around corners left out", walls);
    krow("linear baseline, 1 deg left out", linearStats);
    const auto& r = map.report();
    std::printf("\nflow: scene %d Newton steps (residual %.1e), display %d (residual %.1e); "
                "fourth corner: scene %.2e, display %.2e from -i; nadir: scene %.1e, display %.1e\n",
                r.scene.flow.iterations, r.scene.flow.maxCurvatureError, r.display.flow.iterations,
                r.display.flow.maxCurvatureError, std::abs(r.sceneTips[3] - Complex(0, -1)),
                std::abs(r.displayTips[3] - Complex(0, -1)), std::abs(r.sceneNadir), std::abs(r.displayNadir));
    return 0;
}

/// For a display without a closed form: the baked map's distortion, G o F, and the map against
/// one built on a finer mesh (its convergence), away from the boundary's corners.
int runDisplay(int size, int resolution, int referenceResolution, const std::string& boxName) {
    const CaveBox box = boxNamed(boxName);
    ConformalMapSettings settings;
    settings.box = box;
    settings.mesh.resolution = resolution;
    const auto start = std::chrono::steady_clock::now();
    const ConformalMap map(settings);
    const double mapTime = seconds(start);
    settings.mesh.resolution = referenceResolution;
    const ConformalMap fine(settings);
    const auto bakeStart = std::chrono::steady_clock::now();
    const CubeMap baked = bakeCubeMap(map, box, MapKind::Conformal, size);
    const double bakeTime = seconds(bakeStart);
    std::printf("box %s lacking %s: map res %d built in %.2f s, %d^2 bake in %.2f s; reference res %d\n",
                boxName.c_str(), boxFaceNames(box.missingFaces).c_str(), resolution, mapTime, size, bakeTime,
                referenceResolution);
    const auto& r = map.report();
    std::printf("flow residuals: scene %.1e, display %.1e; alignment sector %d; tips' images differ by up to %.3f "
                "degrees on the disk\n",
                r.scene.flow.maxCurvatureError, r.display.flow.maxCurvatureError, r.alignmentSector,
                r.tipMismatchDegrees);
    std::vector<glm::dvec3> corners;
    for (const int c : boundaryCorners(box)) corners.push_back(boxCornerDirection(box, c));
    std::mt19937 random(11);
    std::normal_distribution<double> normal;
    std::vector<double> inverse, convergence, baked3;
    for (int k = 0; k < 200000; ++k) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(normal(random), normal(random), normal(random)));
        if (isMissingDirection(box, d)) continue;
        double nearest = 10.0;
        for (const auto& c : corners) nearest = std::min(nearest, angleBetween(d, c));
        if (nearest < 3.0 / kDegrees) continue;
        const glm::dvec3 scene = map.sceneFromDisplay(d);
        inverse.push_back(angleBetween(map.displayFromScene(scene), d));
        convergence.push_back(angleBetween(fine.sceneFromDisplay(d), scene));
        baked3.push_back(angleBetween(glm::normalize(glm::dvec3(sampleCubeMapBilinear(baked, d))), scene));
    }
    auto row = [](const char* name, const std::vector<double>& e) {
        std::printf("| %s | %zu | %.2e | %.2e | %.2e |\n", name, e.size(), percentile(e, 0.5) * kDegrees,
                    percentile(e, 0.99) * kDegrees, percentile(e, 1.0) * kDegrees);
    };
    std::printf("\n| angle (degrees), > 3 deg from the boundary's corners | directions | median | p99 | max |\n"
                "|---|---|---|---|---|\n");
    row("G o F - identity (map itself)", inverse);
    row("map vs the map at the reference resolution", convergence);
    row("baked map, bilinear, vs the map", baked3);
    std::printf("\n| K = sigma_max / sigma_min | texels | mean K - 1 | p99 K - 1 | max K | folded texels |\n");
    std::printf("|---|---|---|---|---|---|\n");
    auto krow = [](const std::string& name, const DistortionStatistics& s) {
        std::printf("| %s | %ld | %.2e | %.2e | %.3f | %ld |\n", name.c_str(), s.texelCount, s.meanK - 1.0,
                    s.p99K - 1.0, s.maxK, s.foldedTexels);
    };
    for (const double exclusion : {1.0, 3.0, 5.0}) {
        krow("conformal, " + std::to_string(static_cast<int>(exclusion)) + " deg around corners left out",
             distortionStatistics(baked, exclusion));
    }
    const CubeMap linear = bakeCubeMap(LinearMap(box), box, MapKind::Linear, size);
    krow("linear baseline, 1 deg left out", distortionStatistics(linear, 1.0));
    return 0;
}

int runTiming(int size, int resolution) {
    const auto cacheDir = std::filesystem::temp_directory_path() / "conformal_measure_cache";
    std::filesystem::remove_all(cacheDir);
    setenv("CVC_CACHE_DIR", cacheDir.c_str(), 1);
    BakeSettings settings;
    settings.size = size;
    settings.box = immersiveCabinBox();
    settings.mesh.resolution = resolution;
    auto start = std::chrono::steady_clock::now();
    BakeReport first;
    cachedCubeMap(settings, &first);
    const double total = seconds(start);
    start = std::chrono::steady_clock::now();
    BakeReport second;
    const CubeMap loaded = cachedCubeMap(settings, &second);
    const double load = seconds(start);
    std::printf("| %d | %d | %.2f | %.2f | %.2f | %.3f | %s |\n", size, resolution, first.mapSeconds, first.bakeSeconds,
                total, load, second.wasLoadedFromCache ? "yes" : "NO");
    std::filesystem::remove_all(cacheDir);
    return loaded.size == size ? 0 : 1;
}

int runImages(int resolution, const std::string& outDir) {
    std::filesystem::create_directories(outDir);
    for (const std::string boxName : {"cube", "cabin", "cave4"}) {
        const CaveBox box = boxNamed(boxName);
        ConformalMapSettings settings;
        settings.box = box;
        settings.mesh.resolution = resolution;
        const ConformalMap map(settings);
        const LinearMap linear(box);
        const int size = 256;
        const CubeMap cube = bakeCubeMap(map, box, MapKind::Conformal, size);
        const auto jacobians = cubeMapJacobians(cube);
        const CubeMap linearCube = bakeCubeMap(linear, box, MapKind::Linear, size);
        const auto linearJacobians = cubeMapJacobians(linearCube);
        // Equirectangular grid of display directions: longitude atan2(z, x), latitude asin(y).
        const int width = 1024, height = 512;
        std::ofstream out(outDir + "/conformal_" + boxName + ".f32", std::ios::binary);
        for (int j = 0; j < height; ++j) {
            const double latitude = std::numbers::pi / 2 - (j + 0.5) * std::numbers::pi / height;
            for (int i = 0; i < width; ++i) {
                const double longitude = -std::numbers::pi + (i + 0.5) * 2 * std::numbers::pi / width;
                const glm::dvec3 d(std::cos(latitude) * std::cos(longitude), std::sin(latitude),
                                   std::cos(latitude) * std::sin(longitude));
                const glm::dvec3 s = map.sceneFromDisplay(d);
                const glm::dvec3 l = linear.sceneFromDisplay(d);
                const CubeFaceCoordinate c = cubeFaceFromDirection(d);
                const int ti = std::min(size - 1, static_cast<int>(c.s * size));
                const int tj = std::min(size - 1, static_cast<int>(c.t * size));
                const std::size_t texel = (static_cast<std::size_t>(c.face) * size + tj) * size + ti;
                const float values[9] = {float(s.x), float(s.y), float(s.z), float(l.x), float(l.y), float(l.z),
                                         float(jacobians[texel].quasiConformal),
                                         float(linearJacobians[texel].quasiConformal),
                                         isMissingDirection(box, d) ? 1.0f : 0.0f};
                out.write(reinterpret_cast<const char*>(values), sizeof(values));
            }
        }
        std::printf("wrote %s/conformal_%s.f32 (%d x %d x 9 float32)\n", outDir.c_str(), boxName.c_str(), width, height);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string mode = argc > 1 ? argv[1] : "";
    try {
        if (mode == "phi6" && argc > 2) {
            std::vector<int> resolutions;
            for (int k = 2; k < argc; ++k) resolutions.push_back(std::atoi(argv[k]));
            return runPhi6(resolutions);
        }
        if (mode == "accuracy" && argc == 6) {
            return runAccuracy(std::atoi(argv[2]), std::atoi(argv[3]), std::atoi(argv[4]), argv[5]);
        }
        if (mode == "display" && argc == 6) {
            return runDisplay(std::atoi(argv[2]), std::atoi(argv[3]), std::atoi(argv[4]), argv[5]);
        }
        if (mode == "timing" && argc == 4) return runTiming(std::atoi(argv[2]), std::atoi(argv[3]));
        if (mode == "images" && argc == 4) return runImages(std::atoi(argv[2]), argv[3]);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "conformal_measure: %s\n", e.what());
        return 1;
    }
    std::fprintf(stderr,
                 "usage: conformal_measure phi6 RES... | accuracy N RES REF_RES cube|cabin | timing N RES | "
                 "images RES OUT_DIR | display N RES REF_RES cube|cabin|cave4\n");
    return 2;
}
