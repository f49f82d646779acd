#include "engine/sequence/sequence_dicom.h"

#include <filesystem>

#include "engine/output/png_reader.h"

namespace engine {
namespace {

namespace fs = std::filesystem;

/// One new series of pictures of a frame: its UID, number and description.
struct Series {
    volumes::SecondaryCapture capture;
    int nextInstance = 1;
};

}  // namespace

SequenceDicomSummary writeSequenceDicom(const SequenceJob& job, const std::string& sequenceFolder,
                                        const std::string& dicomFolder, const volumes::DicomIdentifiers& identifiers,
                                        bool force) {
    fs::create_directories(dicomFolder);
    SequenceDicomSummary summary;
    const bool hasBeforeAfter = job.isWritingBeforeAfter && job.display.map != conformal::MapKind::None;
    int seriesNumber = 1;
    const auto newSeries = [&](const std::string& description) {
        Series series;
        series.capture.identifiers = identifiers;
        series.capture.seriesInstanceUid = volumes::newDicomUid();
        series.capture.seriesNumber = seriesNumber++;
        series.capture.seriesDescription = description;
        ++summary.series;
        return series;
    };
    const auto write = [&](Series& series, const fs::path& png, const std::string& dicomName, const std::string& what) {
        const colon::RgbaImage picture = readPng(png.string());
        series.capture.instanceNumber = series.nextInstance++;
        series.capture.imageComments = what;
        volumes::writeSecondaryCapture((fs::path(dicomFolder) / dicomName).string(), picture.width, picture.height,
                                       picture.rgba, series.capture, force);
        ++summary.files;
    };
    for (std::size_t i = 0; i < job.poses.size(); ++i) {
        const int index = static_cast<int>(i);
        const std::string frame = frameFolderName(index);
        const fs::path frameFolder = fs::path(sequenceFolder) / frame;
        const std::string prefix = "cvc " + job.display.name + " " + frame + " ";
        for (Eye eye : {Eye::Left, Eye::Right}) {
            Series series = newSeries(prefix + eyeText(eye) + " eye");
            for (const DisplayWall& wall : job.display.walls) {
                const std::string name = wallNameText(wall.name);
                write(series, frameFolder / eyeText(eye) / (name + ".png"), frame + "_" + eyeText(eye) + "_" + name + ".dcm",
                      eyeText(eye) + " eye, " + name + " wall");
            }
        }
        Series sheet = newSeries(prefix + "review sheet");
        write(sheet, frameFolder / "sheet.png", frame + "_sheet.dcm",
              "review sheet: left eye, right eye, red-cyan anaglyph");
        if (hasBeforeAfter) {
            Series beforeAfter = newSeries(prefix + "centre eye without and with the map");
            write(beforeAfter, frameFolder / "before_after.png", frame + "_before_after.dcm",
                  "centre eye: the walls without the map beside the walls with it");
        }
    }
    return summary;
}

}  // namespace engine
