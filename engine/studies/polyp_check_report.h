/// @brief What polyp-check writes from its results: one JSON entry per result, every rank's
/// entries in the order one process gives them, the document (polyp_check.json) with its plan
/// and worst errors, the Markdown table, the worst errors as text, and the side-by-side crops.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/studies/polyp_check.h"

namespace engine {

/// Where the checked volume and truth came from, and the warp's name as asked for.
struct PolypCheckSources {
    std::string volumePath;
    std::string truthPath;
    std::string warpName;
};

/// One JSON entry per result, in the results' order.
nlohmann::json polypResultEntries(const std::vector<PolypViewResult>& results, const PolypCheckPlan& plan);

/// The entries of several lists (JSON array texts of polypResultEntries, one per rank) in the
/// order one process gives them: map, polyp (as asked for), pose, eye.
std::vector<nlohmann::json> polypEntriesInOrder(const std::vector<std::string>& entryLists, const PolypCheckJob& job,
                                                const PolypCheckPlan& plan);

/// The check's document (polyp_check.json) around the result entries: sources, display, plan
/// and the rule, and the worst errors over polyps of 6 mm and more on the missing walls.
nlohmann::json polypCheckDocument(const nlohmann::json& list, const PolypCheckSources& sources,
                                  const PolypCheckJob& job, const PolypCheckPlan& plan);

/// The entries as a Markdown table, one row per result.
std::string polypCheckMarkdown(const nlohmann::json& entries);

/// The document's worst aspect and circularity errors per map, one line each.
std::string polypCheckWorstText(const nlohmann::json& document);

/// Throws std::runtime_error naming `folder` when it is a file, or holds an earlier check
/// (polyp_check.json, polyp_check.md or crops/) and `force` is false.
void requirePolypCheckFolder(const std::filesystem::path& folder, bool force);

/// Writes the document as folder/polyp_check.json and its table as folder/polyp_check.md.
void writePolypCheckFiles(const std::filesystem::path& folder, const nlohmann::json& document);

/// Reference | conformal | linear | none crops of each polyp, pose and eye side by side, one PNG
/// each in `folder` (polyp_P_POSE_EYE.png).
void writePolypCrops(const std::vector<PolypViewResult>& results, const std::filesystem::path& folder, int cropSize);

}  // namespace engine
