#include "engine/sequence/frame_sequence.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <iomanip>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "engine/display/display_json.h"
#include "engine/output/hit_image_writer.h"
#include "engine/output/png_reader.h"
#include "engine/output/png_writer.h"
#include "engine/review/review_page.h"
#include "engine/review/review_sheet.h"
#include "engine/sequence/sheet_walls_message.h"

namespace engine {
namespace {

namespace fs = std::filesystem;

constexpr Eye kStereoEyes[] = {Eye::Left, Eye::Right};

std::string readText(const fs::path& path) {
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

/// The manifest without the renderer (device, driver): a resumed run may use another driver
/// version, which renders the same images.
nlohmann::json comparablePart(const std::string& manifest) {
    nlohmann::json document = nlohmann::json::parse(manifest, nullptr, false);
    if (document.is_object()) document.erase("renderer");
    return document;
}

/// The manifest, the frames (finished and partial) and the review page that the caller writes
/// beside them (review_page.h): what --force may remove.
bool isOurEntry(const fs::path& entry) {
    const std::string name = entry.filename().string();
    const std::vector<std::string> page = reviewPageFileNames();
    const bool isPageFile = std::find(page.begin(), page.end(), name) != page.end() ||
                            std::any_of(page.begin(), page.end(), [&](const std::string& file) {
                                return name == "." + file + ".partial";
                            });
    return name == "render.json" || name.rfind("frame_", 0) == 0 || name.rfind(".frame_", 0) == 0 || isPageFile;
}

/// Removes our earlier output (only ours) when forced, and writes the manifest.
void prepareFolder(const std::string& manifest, const SequenceOutput& output) {
    const fs::path folder(output.folder);
    if (output.isForced && fs::is_directory(folder)) {
        for (const auto& entry : fs::directory_iterator(folder)) {
            if (isOurEntry(entry.path())) fs::remove_all(entry.path());
        }
    }
    fs::create_directories(folder);
    if (access(folder.c_str(), W_OK) != 0) throw std::runtime_error(output.folder + ": folder is not writable");
    std::ofstream(folder / "render.json") << manifest;
}

RgbaImage toRgba(RenderedImage&& image) { return RgbaImage{image.width, image.height, std::move(image.rgba)}; }

/// The display's walls at the size downsampled() gives them.
Display scaledDisplay(const Display& display, int reduction) {
    Display scaled = display;
    for (auto& wall : scaled.walls) {
        wall.width = (wall.width + reduction - 1) / reduction;
        wall.height = (wall.height + reduction - 1) / reduction;
    }
    return scaled;
}

/// Reduction that brings a cross of `display`'s walls to about `targetWidth` pixels.
int sheetReduction(const Display& display, int targetWidth) {
    int width = 0;
    for (WallName name : {WallName::Left, WallName::Front, WallName::Right, WallName::Back}) {
        int w = 0;
        for (const auto& wall : display.walls) {
            if (wall.name == name) w = wall.width;
        }
        width += w > 0 ? w : 512;
    }
    return std::max(1, (width + targetWidth - 1) / targetWidth);
}

ScenePose scenePoseOf(const SequenceJob& job, int index) {
    const CameraPose& pose = job.poses[static_cast<std::size_t>(index)];
    return ScenePose{pose.positionMm, pose.forward, pose.up, job.mmPerMetre};
}

std::vector<RenderRequest> wallRequests(const Display& display, const ScenePose& pose, std::span<const Eye> eyes,
                                        const RenderSettings& settings, WarpMode warpMode) {
    std::vector<RenderRequest> requests;
    for (Eye eye : eyes) {
        for (const auto& wall : display.walls) {
            const WallView view = wallView(display, wall.name, eye, pose, warpMode);
            requests.push_back({view.rays, settings, view.warp});
        }
    }
    return requests;
}

/// Throws SequenceCancelled when the caller's hook asks to stop.
void throwIfCancelled(const SequenceHooks& hooks) {
    if (hooks.isCancelled && hooks.isCancelled()) throw SequenceCancelled("cancelled");
}

/// `images` rendered for `eyes` (eye after eye, walls in the display's order), labelled.
std::vector<WallImage> labelledWalls(const Display& display, std::span<const Eye> eyes,
                                     std::vector<RenderedImage> images) {
    std::vector<WallImage> walls;
    std::size_t i = 0;
    for (Eye eye : eyes) {
        for (const auto& wall : display.walls) walls.push_back({eye, wall.name, std::move(images.at(i++))});
    }
    return walls;
}

/// One frame on its way: what was asked of the device, and the images once collected.
struct FrameInFlight {
    int index = 0;
    std::optional<RenderBatch> batch;
    std::vector<RenderedImage> images;  // stereo walls (eye after eye), then before/after walls
};

/// Runs `tasks` on up to `threads` workers and rethrows the first exception any of them threw.
void runParallel(std::vector<std::function<void()>>& tasks, unsigned threads) {
    std::atomic<std::size_t> next{0};
    auto worker = [&] {
        for (std::size_t i = next++; i < tasks.size(); i = next++) tasks[i]();
    };
    std::vector<std::future<void>> workers;
    for (unsigned t = 1; t < threads && t < tasks.size(); ++t) workers.push_back(std::async(std::launch::async, worker));
    std::exception_ptr failure;
    try {
        worker();
    } catch (...) {
        failure = std::current_exception();
        next = tasks.size();  // the others stop after their current task
    }
    for (auto& w : workers) {
        try {
            w.get();
        } catch (...) {
            if (!failure) failure = std::current_exception();
        }
    }
    if (failure) std::rethrow_exception(failure);
}

/// Which of a frame's stereo images (eye after eye, walls in the display's order) a rank
/// renders and writes.
std::vector<bool> imagesOfRank(const SequenceShare& share, std::size_t wallCount) {
    std::vector<bool> mine(2 * wallCount, true);
    if (share.ranks > 1 && share.distribution == Distribution::Walls) {
        for (std::size_t i = 0; i < mine.size(); ++i) {
            mine[i] = static_cast<int>((i % wallCount) % static_cast<std::size_t>(share.ranks)) == share.rank;
        }
    }
    return mine;
}

/// Writes a collected frame into its hidden folder (images encoded on worker threads), then
/// renames the folder into place. A rank that shares the frame writes only its images
/// (write(frame, false)): its walls under the walls distribution, the whole frame but the sheet
/// under the frames distribution; rank 0 finishes the frame once all are written (finish).
class FrameWriter {
public:
    FrameWriter(const SequenceJob& job, const fs::path& folder, const SequenceHooks& hooks, std::vector<bool> mine)
        : mJob(job), mFolder(folder), mHooks(hooks), mMine(std::move(mine)), mReduction(sheetReduction(job.display, 1000)),
          mSheetDisplay(scaledDisplay(job.display, mReduction)),
          mThreads(std::max(1u, std::thread::hardware_concurrency())) {}

    /// The frame's images (this rank's), and with `isWhole` its sheet and its move into place.
    /// Returns the walls reduced for the sheet when not whole (empty for other ranks' walls).
    std::vector<RgbaImage> write(FrameInFlight& frame, bool isWhole) {
        const fs::path partial = mFolder / partialFrameFolderName(frame.index);  // cleared by rank 0 before any began
        try {
            std::vector<RgbaImage> reduced = writeImages(frame, partial);
            if (!isWhole) return reduced;
            finish(frame.index, partial, std::move(reduced));
            return {};
        } catch (...) {
            std::error_code ignored;
            fs::remove_all(partial, ignored);
            throw;
        }
    }

    /// The sheet of frame `index` from its walls reduced for it (eye after eye), into `hidden`
    /// where the frame's images are, and the frame into place.
    void finish(int index, const fs::path& hidden, std::vector<RgbaImage> reduced) {
        writeSheet(hidden, std::move(reduced));
        fs::rename(hidden, mFolder / frameFolderName(index));
    }

    /// Rank 0 under the walls distribution, once every rank wrote its walls of frame `index` in
    /// `partial`, or on resuming a stopped run's ".written" frame: the sheet from the files, and
    /// the frame into place.
    void finish(int index, const fs::path& partial) {
        const auto& walls = mJob.display.walls;
        std::vector<RgbaImage> reduced(2 * walls.size());
        std::vector<std::function<void()>> tasks;
        for (std::size_t i = 0; i < reduced.size(); ++i) {
            tasks.emplace_back([&, i] {
                const fs::path file = partial / eyeText(kStereoEyes[i / walls.size()]) /
                                      (wallNameText(walls[i % walls.size()].name) + ".png");
                reduced[i] = downsampled(readPng(file.string()), mReduction);
            });
        }
        runParallel(tasks, mThreads);
        finish(index, partial, std::move(reduced));
    }

private:
    /// This rank's full-size walls to PNG (and hits), each also reduced for the sheet, in
    /// parallel, and the before/after sheet where it was rendered. Returns the reduced walls
    /// (empty images for other ranks' walls).
    std::vector<RgbaImage> writeImages(FrameInFlight& frame, const fs::path& partial) {
        const auto& walls = mJob.display.walls;
        const std::size_t wallCount = walls.size();
        for (Eye eye : kStereoEyes) fs::create_directories(partial / eyeText(eye));

        std::vector<RgbaImage> reduced(2 * wallCount);
        std::vector<std::function<void()>> tasks;
        for (std::size_t i = 0; i < 2 * wallCount; ++i) {
            if (!mMine[i]) continue;
            tasks.emplace_back([&, i] {
                throwIfCancelled(mHooks);
                const fs::path eyeFolder = partial / eyeText(kStereoEyes[i / wallCount]);
                const std::string wallName = wallNameText(walls[i % wallCount].name);
                RenderedImage& image = frame.images[i];
                writePng((eyeFolder / (wallName + ".png")).string(), image.width, image.height, image.rgba, true,
                         mJob.png);
                if (mJob.isWritingHits) {
                    writeHitPositionsNrrd((eyeFolder / (wallName + "_hits.nrrd")).string(), image.width, image.height,
                                          image.hitMm, true);
                }
                reduced[i] = downsampled(toRgba(std::move(image)), mReduction);
            });
        }
        if (frame.images.size() == 4 * wallCount) {
            tasks.emplace_back([&] {
                throwIfCancelled(mHooks);
                std::map<WallName, RgbaImage> before, after;
                for (std::size_t w = 0; w < wallCount; ++w) {
                    before[walls[w].name] = downsampled(toRgba(std::move(frame.images[2 * wallCount + w])), mReduction);
                    after[walls[w].name] = downsampled(toRgba(std::move(frame.images[3 * wallCount + w])), mReduction);
                }
                const RgbaImage beforeAfter =
                    sideBySide({crossLayout(mSheetDisplay, before), crossLayout(mSheetDisplay, after)}, 16);
                writePng((partial / "before_after.png").string(), beforeAfter.width, beforeAfter.height,
                         beforeAfter.rgba, true, mJob.png);
            });
        }
        runParallel(tasks, mThreads);
        throwIfCancelled(mHooks);
        return reduced;
    }

    /// The review sheet: left eye, right eye, anaglyph.
    void writeSheet(const fs::path& partial, std::vector<RgbaImage> reduced) {
        const auto& walls = mJob.display.walls;
        const std::size_t wallCount = walls.size();
        std::map<Eye, std::map<WallName, RgbaImage>> sheetWalls;
        for (std::size_t i = 0; i < 2 * wallCount; ++i) {
            sheetWalls[kStereoEyes[i / wallCount]][walls[i % wallCount].name] = std::move(reduced[i]);
        }
        std::map<WallName, RgbaImage> anaglyph;
        for (const auto& [name, left] : sheetWalls[Eye::Left]) {
            anaglyph[name] = anaglyphOf(left, sheetWalls[Eye::Right].at(name));
        }
        const RgbaImage sheet = sideBySide({crossLayout(mSheetDisplay, sheetWalls[Eye::Left]),
                                            crossLayout(mSheetDisplay, sheetWalls[Eye::Right]),
                                            crossLayout(mSheetDisplay, anaglyph)},
                                           kSheetGapPixels);
        writePng((partial / "sheet.png").string(), sheet.width, sheet.height, sheet.rgba, true, mJob.png);
    }

    const SequenceJob& mJob;
    fs::path mFolder;
    const SequenceHooks& mHooks;
    std::vector<bool> mMine;
    int mReduction;
    Display mSheetDisplay;  // the display's walls at the sheets' reduced size
    unsigned mThreads;
};

std::string modeText(RenderMode mode) { return mode == RenderMode::Composite ? "composite" : "iso"; }
std::string filterText(VolumeFilter filter) { return filter == VolumeFilter::Tricubic ? "tricubic" : "trilinear"; }

}  // namespace

std::vector<WallImage> renderWalls(Raycaster& raycaster, const Display& display, const ScenePose& pose,
                                   std::span<const Eye> eyes, const RenderSettings& settings, WarpMode warpMode) {
    validateDisplay(display);
    const std::vector<RenderRequest> requests = wallRequests(display, pose, eyes, settings, warpMode);
    RenderBatch batch = raycaster.submit(requests);
    return labelledWalls(display, eyes, raycaster.collect(batch));
}

std::string frameFolderName(int index) {
    std::ostringstream name;
    name << "frame_" << std::setw(4) << std::setfill('0') << index;
    return name.str();
}

std::string partialFrameFolderName(int index) { return '.' + frameFolderName(index) + ".partial"; }

std::string writtenFrameFolderName(int index) { return '.' + frameFolderName(index) + ".written"; }

std::vector<int> framesOfRank(const std::vector<int>& pending, const SequenceShare& share, int rank) {
    if (share.ranks <= 1 || share.distribution == Distribution::Walls) return pending;
    std::vector<int> frames;
    for (std::size_t i = static_cast<std::size_t>(std::max(rank, 0)); i < pending.size();
         i += static_cast<std::size_t>(share.ranks)) {
        frames.push_back(pending[i]);
    }
    return frames;
}

void checkSequenceOutput(const SequenceJob& job, const SequenceOutput& output) {
    const fs::path folder(output.folder);
    if (fs::exists(folder) && !fs::is_directory(folder)) {
        throw std::runtime_error(output.folder + ": exists and is not a folder");
    }
    const auto isCompanion = [&](const fs::directory_entry& entry) {
        const std::string name = entry.path().filename().string();
        return std::find(output.companions.begin(), output.companions.end(), name) != output.companions.end();
    };
    if (!fs::exists(folder) ||
        std::all_of(fs::directory_iterator(folder), fs::directory_iterator(), isCompanion)) {
        return;
    }
    if (output.isResumed) {
        const fs::path manifestPath = folder / "render.json";
        if (!fs::exists(manifestPath)) {
            throw std::runtime_error(output.folder + ": holds no render.json, so there is nothing to resume");
        }
        if (comparablePart(readText(manifestPath)) != comparablePart(sequenceManifest(job))) {
            throw std::runtime_error(output.folder + ": was rendered with other inputs or settings (see its "
                                     "render.json); pass --force to replace it");
        }
    } else if (!output.isForced) {
        throw std::runtime_error(output.folder +
                                 ": exists and is not empty (pass --resume to continue it or --force to replace it)");
    }
}

nlohmann::json sequenceSummaryJson(const SequenceJob& job, const SequenceSummary& summary, const std::string& folder) {
    const int wallImages = summary.framesRendered * static_cast<int>(std::size(kStereoEyes) * job.display.walls.size());
    nlohmann::json document;
    document["display"] = job.display.name;
    document["renderer"] = job.rendererDescription;
    document["frames_total"] = job.poses.size();
    document["frames_rendered"] = summary.framesRendered;
    document["frames_kept"] = summary.framesKept;
    document["frames_left_half_written"] = summary.framesLeftHalfWritten;
    document["frames_finished_from_images"] = summary.framesFinishedFromImages;
    document["wall_images"] = wallImages;
    document["seconds"] = summary.seconds;
    const bool isAny = summary.framesRendered > 0;
    document["seconds_per_frame"] = isAny ? nlohmann::json(summary.seconds / summary.framesRendered) : nlohmann::json();
    document["ray_casting_ms_per_stereo_frame"] =
        isAny ? nlohmann::json(summary.rayCastingMs / summary.framesRendered) : nlohmann::json();
    document["folder"] = fs::absolute(folder).string();
    document["review_page"] = (fs::absolute(folder) / "index.html").string();
    return document;
}

std::string sequenceManifest(const SequenceJob& job) {
    const RenderSettings& s = job.settings;
    nlohmann::json manifest;
    manifest["volume"] = job.volumePath.empty() ? "" : fs::absolute(job.volumePath).string();
    manifest["display"] = nlohmann::json::parse(displayJson(job.display));
    manifest["map"] = job.mapSource;
    manifest["warp"] = warpModeName(job.warpMode);
    manifest["mm_per_metre"] = job.mmPerMetre;
    manifest["before_after"] = job.isWritingBeforeAfter;
    manifest["hits"] = job.isWritingHits;
    manifest["settings"] = {{"mode", modeText(s.mode)},
                            {"iso_hu", s.isoHu},
                            {"transfer_function", s.transferFunction},
                            {"step_voxels", s.stepVoxels},
                            {"refinement_steps", s.refinementSteps},
                            {"filter", filterText(s.filter)},
                            {"gradient", gradientFilterName(s.gradient)},
                            {"gradient_volume", s.isUsingGradientVolume},
                            {"skipping", s.isSkipping},
                            {"skip_cell_voxels", s.skipCellVoxels},
                            {"start_pass", s.isUsingRayStartPass},
                            {"look_in_every_tile", s.isLookingInEveryTile},
                            {"skip_bent_rays", s.isSkippingBentRays},
                            {"adaptive", s.isAdaptive},
                            {"early_termination", s.earlyTerminationOpacity},
                            {"jitter", s.isJittered},
                            {"jitter_seed", s.jitterSeed},
                            {"light_half_distance_mm", s.lightHalfDistanceMm}};
    nlohmann::json poses = nlohmann::json::array();
    for (const auto& pose : job.poses) {
        poses.push_back({{"position_mm", {pose.positionMm.x, pose.positionMm.y, pose.positionMm.z}},
                         {"forward", {pose.forward.x, pose.forward.y, pose.forward.z}},
                         {"up", {pose.up.x, pose.up.y, pose.up.z}}});
    }
    manifest["poses"] = poses;
    manifest["renderer"] = job.rendererDescription;
    return manifest.dump(2) + "\n";
}

SequenceSummary renderSequence(Raycaster& raycaster, const SequenceJob& job, const SequenceOutput& output,
                               const SequenceHooks& hooks, const SequenceShare& share) {
    validateDisplay(job.display);
    const bool isShared = share.ranks > 1;
    const bool isSharingWalls = isShared && share.distribution == Distribution::Walls;
    const bool isSharingFrames = isShared && !isSharingWalls;
    const bool hasMessages = share.rank == 0 ? static_cast<bool>(share.takeFrameWritten)
                                             : static_cast<bool>(share.reportFrameWritten);
    if (share.ranks < 1 || share.rank < 0 || share.rank >= share.ranks || (isShared && !share.barrier) ||
        (isSharingFrames && !hasMessages)) {
        throw std::invalid_argument("sequence share: rank " + std::to_string(share.rank) + " of " +
                                    std::to_string(share.ranks) +
                                    " (a shared sequence needs a barrier, and sharing frames a way to tell rank 0)");
    }
    if (isSharingWalls && share.ranks > static_cast<int>(job.display.walls.size())) {
        throw std::invalid_argument("walls distribution: " + std::to_string(share.ranks) + " ranks for a display of " +
                                    std::to_string(job.display.walls.size()) +
                                    " walls (at most one rank per wall; distribute frames instead)");
    }
    const auto barrier = [&] {
        if (isShared) share.barrier();
    };
    checkSequenceOutput(job, output);
    barrier();  // every rank checked the folder before rank 0 changes it
    const fs::path folder(output.folder);
    const int total = static_cast<int>(job.poses.size());
    std::vector<int> pending;
    if (share.rank == 0) prepareFolder(sequenceManifest(job), output);
    barrier();  // the folder is ready, and every rank sees the same finished frames
    for (int i = 0; i < total; ++i) {
        if (!fs::is_directory(folder / frameFolderName(i))) pending.push_back(i);
    }
    SequenceSummary summary;
    // A ".written" frame of a stopped run has every image: only its sheet is missing, which
    // rank 0 composes from the files (as under the walls distribution). A ".partial" one is
    // rendered again. Every rank sees the same folders here, so all agree on what is left.
    std::vector<int> unfinished;
    for (int index : pending) {
        if (fs::is_directory(folder / writtenFrameFolderName(index))) {
            summary.framesFinishedFromImages.push_back(index);
            continue;
        }
        if (fs::exists(folder / partialFrameFolderName(index))) summary.framesLeftHalfWritten.push_back(index);
        unfinished.push_back(index);
    }
    pending = std::move(unfinished);
    barrier();  // every rank looked before rank 0 clears the hidden folders
    if (share.rank == 0) {
        for (int index : pending) {  // left by a run that stopped
            fs::remove_all(folder / partialFrameFolderName(index));
            fs::remove_all(folder / writtenFrameFolderName(index));
        }
    }
    barrier();
    const auto start = std::chrono::steady_clock::now();

    summary.framesKept =
        total - static_cast<int>(pending.size()) - static_cast<int>(summary.framesFinishedFromImages.size());
    const std::vector<int> mine = framesOfRank(pending, share, share.rank);
    if (hooks.onPendingFrames) hooks.onPendingFrames(pending);
    // Rank 0 reports the whole job: the frames in place in the folder, whoever rendered them.
    // It moves every finished frame into place itself, so it counts them as it does.
    int framesInPlace = summary.framesKept;
    const auto reportProgress = [&] {
        if (share.rank != 0 || !hooks.onProgress) return;
        hooks.onProgress(framesInPlace, total);
    };
    reportProgress();

    RenderSettings stereoSettings = job.settings;
    stereoSettings.isWritingHits = job.isWritingHits || job.isComputingHits;
    RenderSettings sheetSettings = job.settings;
    sheetSettings.isWritingHits = false;
    // Under the walls distribution rank 0 renders the before/after walls; otherwise each frame's owner.
    const bool isWritingBeforeAfter = job.isWritingBeforeAfter && job.display.map != conformal::MapKind::None &&
                                      (!isSharingWalls || share.rank == 0);
    const std::size_t stereoCount = 2 * job.display.walls.size();
    const std::vector<bool> myImages = imagesOfRank(share, job.display.walls.size());
    FrameWriter writer(job, folder, hooks, myImages);

    // The device renders frame i while the host writes frame i - 1.
    const auto submitFrame = [&](int index) {
        const ScenePose pose = scenePoseOf(job, index);
        const std::vector<RenderRequest> stereo =
            wallRequests(job.display, pose, kStereoEyes, stereoSettings, job.warpMode);
        std::vector<RenderRequest> requests;
        for (std::size_t i = 0; i < stereo.size(); ++i) {
            if (myImages[i]) requests.push_back(stereo[i]);
        }
        if (isWritingBeforeAfter) {
            const Eye centre[] = {Eye::Centre};
            for (WarpMode warp : {WarpMode::None, job.warpMode}) {
                auto more = wallRequests(job.display, pose, centre, sheetSettings, warp);
                requests.insert(requests.end(), more.begin(), more.end());
            }
        }
        FrameInFlight frame;
        frame.index = index;
        frame.batch.emplace(raycaster.submit(requests));
        return frame;
    };
    const auto collectFrame = [&](FrameInFlight& frame) {
        std::vector<RenderedImage> collected = raycaster.collect(*frame.batch);
        frame.batch.reset();
        // Back in the frame's full order (other ranks' walls left empty), before/after last.
        frame.images.assign(stereoCount, RenderedImage{});
        std::size_t next = 0;
        for (std::size_t i = 0; i < stereoCount; ++i) {
            if (!myImages[i]) continue;
            summary.rayCastingMs += std::max(collected[next].deviceMs, 0.0);
            frame.images[i] = std::move(collected[next++]);
        }
        for (; next < collected.size(); ++next) frame.images.push_back(std::move(collected[next]));
        if (hooks.onFrame && !isSharingWalls) {
            std::vector<RenderedImage> stereo(frame.images.begin(),
                                              frame.images.begin() + static_cast<std::ptrdiff_t>(stereoCount));
            hooks.onFrame(frame.index, labelledWalls(job.display, kStereoEyes, std::move(stereo)));
        }
    };
    // Rank 0 of a shared run: the sheet of a frame whose walls other ranks rendered, timed.
    const auto finishTimed = [&](const std::function<void()>& finish) {
        const auto sheetStart = std::chrono::steady_clock::now();
        finish();
        summary.sheetsOfOtherRanksSeconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - sheetStart).count();
        ++summary.sheetsOfOtherRanks;
    };
    // Rank 0 under the frames distribution: the frames the others reported written.
    const int othersFrames = isSharingFrames && share.rank == 0 ? static_cast<int>(pending.size() - mine.size()) : 0;
    int othersFinished = 0;
    const auto finishOthersFrames = [&] {
        if (othersFinished == othersFrames) return;
        while (std::optional<std::vector<unsigned char>> message = share.takeFrameWritten()) {
            SheetWalls written = unpackSheetWalls(*message);
            if (written.walls.size() != stereoCount || written.frameIndex < 0 || written.frameIndex >= total) {
                throw SheetWallsMessageError("sheet walls message: frame " + std::to_string(written.frameIndex) +
                                             " with " + std::to_string(written.walls.size()) + " walls, not " +
                                             std::to_string(stereoCount));
            }
            finishTimed([&] {
                writer.finish(written.frameIndex, folder / writtenFrameFolderName(written.frameIndex),
                              std::move(written.walls));
            });
            ++othersFinished;
            ++framesInPlace;
            reportProgress();
        }
    };
    const auto writeFrame = [&](FrameInFlight& frame) {
        if (isSharingWalls) {
            writer.write(frame, false);
            barrier();  // every rank's walls of this frame are written
            if (share.rank == 0) {
                finishTimed([&] { writer.finish(frame.index, folder / partialFrameFolderName(frame.index)); });
            }
        } else if (share.rank == 0) {
            writer.write(frame, true);
        } else {
            std::vector<RgbaImage> reduced = writer.write(frame, false);
            fs::rename(folder / partialFrameFolderName(frame.index), folder / writtenFrameFolderName(frame.index));
            share.reportFrameWritten(packSheetWalls({frame.index, std::move(reduced)}));
        }
        if (share.rank == 0) ++framesInPlace;  // under either distribution rank 0 moved it
        reportProgress();
        finishOthersFrames();
    };

    if (share.rank == 0) {
        for (int index : summary.framesFinishedFromImages) {
            throwIfCancelled(hooks);
            writer.finish(index, folder / writtenFrameFolderName(index));
            ++framesInPlace;
            reportProgress();
        }
    }

    std::unique_ptr<FrameInFlight> ready;  // collected, not yet written
    for (int index : mine) {
        throwIfCancelled(hooks);
        auto next = std::make_unique<FrameInFlight>(submitFrame(index));
        if (ready) writeFrame(*ready);
        collectFrame(*next);
        ready = std::move(next);
    }
    if (ready) writeFrame(*ready);
    while (othersFinished < othersFrames) {
        throwIfCancelled(hooks);
        finishOthersFrames();
        if (othersFinished < othersFrames) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    barrier();  // every rank's frames are in place
    summary.framesRendered = static_cast<int>(pending.size());
    if (isShared) reportProgress();  // the other ranks' last frames
    summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
}

}  // namespace engine
