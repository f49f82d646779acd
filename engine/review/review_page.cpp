#include "engine/review/review_page.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "engine/review/review_sheet.h"
#include "engine/review/review_volume.h"
#include "index_html.h"
#include "review_page_css.h"
#include "review_page_js.h"

namespace engine {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;  // the data file keeps the order it is written in, for a reader

json vectorJson(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }

json poseJson(const CameraPose& pose) {
    return {{"position_mm", vectorJson(pose.positionMm)},
            {"forward", vectorJson(pose.forward)},
            {"up", vectorJson(pose.up)}};
}

json labelledJson(const std::vector<std::pair<std::string, std::string>>& rows) {
    json list = json::array();
    for (const auto& [label, value] : rows) list.push_back({{"label", label}, {"value", value}});
    return list;
}

json coverageJson(const ReviewCoverage& coverage) {
    json patches = json::array();
    for (const ReviewPatch& patch : coverage.patches) {
        patches.push_back({{"rank", patch.rank},
                           {"area_mm2", patch.areaMm2},
                           {"centre_mm", vectorJson(patch.centreMm)},
                           {"pose", poseJson(patch.pose)},
                           {"nearest_frame", patch.nearestFrame},
                           {"picture", patch.picture}});
    }
    return {{"percent", coverage.percent},
            {"seen_mm2", coverage.seenMm2},
            {"wall_mm2", coverage.wallMm2},
            {"overview", coverage.overview},
            {"description", coverage.description},
            {"cumulative_percent", coverage.cumulativePercent},
            {"patches", patches}};
}

json candidatesJson(const std::vector<ReviewCandidate>& list) {
    const auto ring = [](const std::optional<SheetRing>& r) {
        return r ? json{{"x", r->x}, {"y", r->y}, {"radius", r->radius}} : json(nullptr);
    };
    json candidates = json::array();
    for (const ReviewCandidate& c : list) {
        candidates.push_back({{"rank", c.rank},
                              {"diameter_mm", c.diameterMm},
                              {"score", c.score},
                              {"shape_index", c.shapeIndex},
                              {"centre_mm", vectorJson(c.centreMm)},
                              {"frame", c.frame},
                              {"picture", c.picture},
                              {"ring", {{"left", ring(c.leftRing)}, {"right", ring(c.rightRing)}}}});
    }
    return candidates;
}

json volumeJson(const ReviewVolume& volume) {
    json views = json::array();
    for (const ReviewSliceView& view : volume.views) {
        views.push_back({{"name", view.name},
                         {"normal_axis", view.normalAxis},
                         {"column_axis", view.columnAxis},
                         {"row_axis", view.rowAxis},
                         {"column_flipped", view.isColumnFlipped},
                         {"row_flipped", view.isRowFlipped},
                         {"labels",
                          {{"left", view.leftLabel},
                           {"right", view.rightLabel},
                           {"top", view.topLabel},
                           {"bottom", view.bottomLabel}}}});
    }
    return {{"dims", volume.dims},
            {"factor", volume.factor},
            {"spacing_mm", vectorJson(volume.spacingMm)},
            {"offset_mm", vectorJson(volume.offsetMm)},
            {"window", {{"width_hu", volume.windowWidthHu}, {"level_hu", volume.windowLevelHu}}},
            {"oblique", volume.isOblique},
            {"direction_lps",  // columns: the grid axes in patient LPS
             json::array({vectorJson(volume.directionLps[0]), vectorJson(volume.directionLps[1]),
                          vectorJson(volume.directionLps[2])})},
            {"views", views},
            {"grey_base64", base64Of(volume.grey)}};
}

/// JSON as a JavaScript statement. ASCII only (other characters escaped), so the file reads the
/// same whatever encoding a browser assumes for a local script; invalid UTF-8 in a name becomes
/// U+FFFD instead of failing the page.
std::string scriptAssigning(const std::string& variable, const json& value, int indent) {
    return "window." + variable + " = " + value.dump(indent, ' ', true, json::error_handler_t::replace) + ";\n";
}

/// Writes `bytes` to folder/name through a temporary file beside it.
void replaceFile(const fs::path& folder, const std::string& name, std::string_view bytes) {
    const fs::path target = folder / name;
    const fs::path temporary = folder / ("." + name + ".partial");
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        out.close();
        if (!out) {
            std::error_code ignored;
            fs::remove(temporary, ignored);
            throw std::runtime_error(target.string() + ": cannot be written");
        }
    }
    fs::rename(temporary, target);
}

template <std::size_t N>
std::string_view embedded(const unsigned char (&bytes)[N]) {
    return {reinterpret_cast<const char*>(bytes), N};
}

json dataJson(const ReviewPage& page) {
    json frames = json::array();
    double arcMm = 0.0;
    for (std::size_t i = 0; i < page.frames.size(); ++i) {
        const ReviewFrame& frame = page.frames[i];
        if (i > 0) arcMm += glm::length(frame.pose.positionMm - page.frames[i - 1].pose.positionMm);
        json images = json::array();
        for (const ReviewImage& image : frame.images) {
            images.push_back({{"label", image.label}, {"path", image.path}, {"group", image.group}});
        }
        json entry = {{"index", frame.index},
                      {"pose", poseJson(frame.pose)},
                      {"arc_mm", arcMm},
                      {"sheet", frame.sheet},
                      {"images", images}};
        if (page.ct) entry["patient_lps_mm"] = vectorJson(volumes::patientFromVolumeMm(*page.ct, frame.pose.positionMm));
        frames.push_back(entry);
    }
    json data = {{"title", page.title},
                 {"facts", labelledJson(page.facts)},
                 {"frames", frames},
                 {"sheet_caption", page.sheetCaption},
                 {"path_length_mm", arcMm},
                 {"coverage", page.coverage ? coverageJson(*page.coverage) : json(nullptr)},
                 {"measurements", labelledJson(page.measurements)}};
    if (!page.candidates.empty()) {  // only then: the pages without candidates stay as they were
        data["candidates"] = candidatesJson(page.candidates);
        data["sheet_gap_px"] = kSheetGapPixels;
    }
    return data;
}

}  // namespace

std::vector<std::string> reviewPageFileNames() {
    return {"index.html", "review_page.js", "review_page.css", "review_data.js", "review_volume.js"};
}

void writeReviewPage(const std::string& folder, const ReviewPage& page) {
    const fs::path dir(folder);
    fs::create_directories(dir);
    // Each file whole (written beside its place, then renamed); the data before the page that
    // reads them.
    replaceFile(dir, "review_volume.js",
                scriptAssigning("REVIEW_VOLUME", page.ct ? volumeJson(reviewVolumeOf(*page.ct)) : json(nullptr), -1));
    replaceFile(dir, "review_data.js", scriptAssigning("REVIEW", dataJson(page), 1));
    replaceFile(dir, "review_page.css", embedded(cvc_embedded::review_page_css));
    replaceFile(dir, "review_page.js", embedded(cvc_embedded::review_page_js));
    replaceFile(dir, "index.html", embedded(cvc_embedded::index_html));
}

}  // namespace engine
