#include "app/frame_sequence.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include <unistd.h>

#include "app/progress_bar.h"
#include "engine/png_writer.h"
#include "engine/review_sheet.h"

namespace app {
namespace {

namespace fs = std::filesystem;

std::atomic<bool> gInterruptRequested{false};

extern "C" void onInterrupt(int) {
    gInterruptRequested = true;
    std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C stops at once
}

/// Installs the Ctrl-C handler for the lifetime of a sequence and restores the old one.
class InterruptGuard {
public:
    InterruptGuard() : mPrevious(std::signal(SIGINT, onInterrupt)) { gInterruptRequested = false; }
    ~InterruptGuard() { std::signal(SIGINT, mPrevious); }
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

private:
    void (*mPrevious)(int);
};

std::string readText(const fs::path& path) {
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

bool isOurEntry(const fs::path& entry) {
    const std::string name = entry.filename().string();
    return name == "render.json" || name.rfind("frame_", 0) == 0 || name.rfind(".frame_", 0) == 0;
}

/// Makes the folder ready: refuses to touch earlier output unless asked, checks a resumed
/// folder's manifest, and removes our earlier output (only ours) when forced.
void prepareFolder(const SequenceJob& job, const SequenceOutput& output) {
    const fs::path folder(output.folder);
    if (fs::exists(folder) && !fs::is_directory(folder)) {
        throw std::runtime_error(output.folder + ": exists and is not a folder");
    }
    if (fs::exists(folder) && !fs::is_empty(folder)) {
        if (output.isResumed) {
            const fs::path manifest = folder / "render.json";
            if (!fs::exists(manifest)) {
                throw std::runtime_error(output.folder + ": holds no render.json, so there is nothing to resume");
            }
            if (readText(manifest) != job.manifestJson) {
                throw std::runtime_error(output.folder + ": was rendered with other inputs or settings (see its "
                                         "render.json); pass --force to replace it");
            }
        } else if (output.isForced) {
            for (const auto& entry : fs::directory_iterator(folder)) {
                if (isOurEntry(entry.path())) fs::remove_all(entry.path());
            }
        } else {
            throw std::runtime_error(output.folder +
                                     ": exists and is not empty (pass --resume to continue it or --force to replace it)");
        }
    }
    fs::create_directories(folder);
    if (access(folder.c_str(), W_OK) != 0) throw std::runtime_error(output.folder + ": folder is not writable");
    std::ofstream(folder / "render.json") << job.manifestJson;
}

engine::RgbaImage toRgba(engine::RenderedImage&& image) {
    return engine::RgbaImage{image.width, image.height, std::move(image.rgba)};
}

void writeImage(const fs::path& path, const engine::RgbaImage& image, int compression) {
    engine::writePng(path.string(), image.width, image.height, image.rgba, true, compression);
}

void checkInterrupt() {
    if (gInterruptRequested) throw Interrupted("interrupted");
}

/// The display's walls at the size downsampled() gives them.
std::vector<engine::DisplayWall> scaledWalls(const engine::Display& display, int reduction) {
    std::vector<engine::DisplayWall> walls = display.walls;
    for (auto& wall : walls) {
        wall.width = (wall.width + reduction - 1) / reduction;
        wall.height = (wall.height + reduction - 1) / reduction;
    }
    return walls;
}

/// Reduction that brings a cross of `display`'s walls to about `targetWidth` pixels.
int sheetReduction(const engine::Display& display, int targetWidth) {
    int width = 0;
    for (engine::WallName name : {engine::WallName::Left, engine::WallName::Front, engine::WallName::Right,
                                  engine::WallName::Back}) {
        int w = 0;
        for (const auto& wall : display.walls) {
            if (wall.name == name) w = wall.width;
        }
        width += w > 0 ? w : 512;
    }
    return std::max(1, (width + targetWidth - 1) / targetWidth);
}

/// Renders the centre eye's walls with `warp` and lays them out as a cross.
engine::RgbaImage centreCross(engine::Raycaster& raycaster, const SequenceJob& job, const engine::ScenePose& pose,
                              engine::WarpMode warpMode, int reduction) {
    std::map<engine::WallName, engine::RgbaImage> walls;
    engine::RenderSettings settings = job.settings;
    settings.isWritingHits = false;
    for (const auto& wall : job.display.walls) {
        checkInterrupt();
        const auto view = engine::wallView(job.display, wall.name, engine::Eye::Centre, pose, warpMode);
        walls[wall.name] = engine::downsampled(toRgba(raycaster.render(view.rays, settings, view.warp)), reduction);
    }
    return engine::crossLayout(engine::Display{job.display.name, job.display.boxSizeM, scaledWalls(job.display, reduction)},
                               walls);
}

/// The hidden folder a frame is rendered into before it is renamed into place.
std::string partialFolderName(int index);

}  // namespace

std::string frameFolderName(int index) {
    std::ostringstream name;
    name << "frame_" << std::setw(4) << std::setfill('0') << index;
    return name.str();
}

namespace {

std::string partialFolderName(int index) {
    std::ostringstream name;
    name << '.' << frameFolderName(index) << ".partial";
    return name.str();
}

}  // namespace

SequenceSummary renderSequence(engine::Raycaster& raycaster, const SequenceJob& job, const SequenceOutput& output) {
    engine::validateDisplay(job.display);
    prepareFolder(job, output);
    const fs::path folder(output.folder);
    const auto start = std::chrono::steady_clock::now();
    InterruptGuard interruptGuard;

    const int total = static_cast<int>(job.poses.size());
    int done = 0;
    for (int i = 0; i < total; ++i) done += fs::is_directory(folder / frameFolderName(i)) ? 1 : 0;
    SequenceSummary summary;
    summary.framesKept = done;
    ProgressBar progress(std::cerr, total, done, isatty(fileno(stderr)) != 0);
    progress.update(done);

    const int reduction = sheetReduction(job.display, 1000);
    engine::RenderSettings settings = job.settings;
    settings.isWritingHits = false;
    for (int i = 0; i < total; ++i) {
        const fs::path finished = folder / frameFolderName(i);
        if (fs::is_directory(finished)) continue;
        const fs::path partial = folder / partialFolderName(i);
        fs::remove_all(partial);
        engine::ScenePose pose{job.poses[static_cast<std::size_t>(i)].positionMm, job.poses[static_cast<std::size_t>(i)].forward,
                               job.poses[static_cast<std::size_t>(i)].up, job.mmPerMetre};
        try {
            std::map<engine::Eye, std::map<engine::WallName, engine::RgbaImage>> sheetWalls;
            for (engine::Eye eye : {engine::Eye::Left, engine::Eye::Right}) {
                const fs::path eyeFolder = partial / engine::eyeText(eye);
                fs::create_directories(eyeFolder);
                for (const auto& wall : job.display.walls) {
                    checkInterrupt();
                    const auto view = engine::wallView(job.display, wall.name, eye, pose, job.warpMode);
                    engine::RenderedImage rendered = raycaster.render(view.rays, settings, view.warp);
                    summary.rayCastingMs += std::max(rendered.deviceMs, 0.0);
                    engine::RgbaImage image = toRgba(std::move(rendered));
                    writeImage(eyeFolder / (engine::wallNameText(wall.name) + ".png"), image, job.pngCompression);
                    sheetWalls[eye][wall.name] = engine::downsampled(image, reduction);
                }
            }
            // The review sheet: left eye, right eye, anaglyph.
            std::map<engine::WallName, engine::RgbaImage> anaglyph;
            for (const auto& [name, left] : sheetWalls[engine::Eye::Left]) {
                anaglyph[name] = engine::anaglyphOf(left, sheetWalls[engine::Eye::Right].at(name));
            }
            const engine::Display sheetDisplay{job.display.name, job.display.boxSizeM, scaledWalls(job.display, reduction)};
            const engine::RgbaImage sheet = engine::sideBySide(
                {engine::crossLayout(sheetDisplay, sheetWalls[engine::Eye::Left]),
                 engine::crossLayout(sheetDisplay, sheetWalls[engine::Eye::Right]),
                 engine::crossLayout(sheetDisplay, anaglyph)},
                16);
            writeImage(partial / "sheet.png", sheet, job.pngCompression);
            if (job.isWritingBeforeAfter && job.display.map != engine::MapChoice::None) {
                const engine::RgbaImage beforeAfter =
                    engine::sideBySide({centreCross(raycaster, job, pose, engine::WarpMode::None, reduction),
                                        centreCross(raycaster, job, pose, job.warpMode, reduction)},
                                       16);
                writeImage(partial / "before_after.png", beforeAfter, job.pngCompression);
            }
            fs::rename(partial, finished);
        } catch (...) {
            std::error_code ignored;
            fs::remove_all(partial, ignored);
            progress.finish();
            throw;
        }
        ++done;
        ++summary.framesRendered;
        progress.update(done);
    }
    progress.finish();
    summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
}

}  // namespace app
