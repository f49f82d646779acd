#include "engine/sequence/sequence_review_page.h"

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace engine {
namespace {

namespace fs = std::filesystem;

std::string renderingText(const RenderSettings& s) {
    std::ostringstream text;
    if (s.mode == RenderMode::Composite) {
        text << "composite, " << s.transferFunction;
    } else {
        text << "iso-surface at " << s.isoHu << " HU";
    }
    text << ", " << (s.filter == VolumeFilter::Tricubic ? "tricubic" : "trilinear") << ", step " << s.stepVoxels
         << " voxel";
    return text.str();
}

/// "front, back, left, right 1400x1050; floor 1050x1050": walls of one size named together.
std::string wallListText(const Display& display) {
    std::vector<std::pair<std::string, std::string>> sizes;  // size, wall names, in the display's order
    for (const DisplayWall& wall : display.walls) {
        const std::string size = std::to_string(wall.width) + "\u00d7" + std::to_string(wall.height);
        auto same = std::find_if(sizes.begin(), sizes.end(), [&](const auto& entry) { return entry.first == size; });
        if (same == sizes.end()) {
            sizes.emplace_back(size, wallNameText(wall.name));
        } else {
            same->second += ", " + wallNameText(wall.name);
        }
    }
    std::string text;
    for (const auto& [size, names] : sizes) text += (text.empty() ? "" : "; ") + names + " " + size;
    return text;
}

std::string scaleText(double mmPerMetre) {
    std::ostringstream text;
    text << mmPerMetre << " mm of volume per CAVE metre";
    return text.str();
}

std::string mapText(const SequenceJob& job) {
    const std::string kind = conformal::mapKindName(job.display.map);
    return job.mapSource.empty() || job.mapSource == kind ? kind : kind + " (" + job.mapSource + ")";
}

}  // namespace

ReviewPage reviewPageOfSequence(const SequenceJob& job, const volumes::Volume* ct) {
    ReviewPage page;
    const std::string volumeName =
        job.volumePath.empty() ? std::string("volume") : fs::path(job.volumePath).filename().string();
    page.title = volumeName + " on " + job.display.name;
    page.facts = {{"volume", job.volumePath.empty() ? "(in memory)"
                                                    : fs::absolute(job.volumePath).lexically_normal().string()},
                  {"display", job.display.name + ": " + wallListText(job.display)},
                  {"map", mapText(job)},
                  {"rendering", renderingText(job.settings)},
                  {"scale", scaleText(job.mmPerMetre)},
                  {"frames", std::to_string(job.poses.size())}};
    if (!job.rendererDescription.empty()) page.facts.emplace_back("renderer", job.rendererDescription);
    page.ct = ct;
    const bool hasBeforeAfter = job.isWritingBeforeAfter && job.display.map != conformal::MapKind::None;
    for (std::size_t i = 0; i < job.poses.size(); ++i) {
        ReviewFrame frame;
        frame.index = static_cast<int>(i);
        frame.pose = job.poses[i];
        const std::string folder = frameFolderName(frame.index);
        frame.sheet = folder + "/sheet.png";
        for (Eye eye : {Eye::Left, Eye::Right}) {
            for (const DisplayWall& wall : job.display.walls) {
                const std::string name = wallNameText(wall.name);
                frame.images.push_back({name, folder + "/" + eyeText(eye) + "/" + name + ".png", eyeText(eye) + " eye"});
            }
        }
        if (hasBeforeAfter) frame.images.push_back({"without / with the map", folder + "/before_after.png", "centre eye"});
        page.frames.push_back(std::move(frame));
    }
    return page;
}

}  // namespace engine
