#include "volumes/load_volume.h"

#include <algorithm>
#include <filesystem>

#include "volumes/dicom_reader.h"
#include "volumes/metaimage_io.h"
#include "volumes/nifti_reader.h"
#include "volumes/nrrd_io.h"
#include "volumes/vdb_io.h"

namespace volumes {
namespace {

bool endsWith(const std::string& text, const std::string& suffix) {
    return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

std::string volumeFormatName(VolumeFormat format) {
    switch (format) {
        case VolumeFormat::DicomSeries: return "DICOM series";
        case VolumeFormat::Nifti: return "NIfTI";
        case VolumeFormat::Nrrd: return "NRRD";
        case VolumeFormat::MetaImage: return "MetaImage";
        case VolumeFormat::Raw: return "raw";
        case VolumeFormat::Vdb: return "OpenVDB";
    }
    return "unknown";
}

VolumeFormat volumeFormatOf(const std::string& path, const LoadOptions& options) {
    std::error_code error;
    const auto status = std::filesystem::status(path, error);
    if (!std::filesystem::exists(status)) throw VolumeError(path + ": no such file or folder");
    // Each option belongs to one kind of input: given with another it would be silently unused.
    if (std::filesystem::is_directory(status)) {
        if (options.raw) throw VolumeError(path + ": a raw description is for a headerless file, this is a folder");
        return VolumeFormat::DicomSeries;
    }
    if (!options.dicomSeriesUid.empty()) {
        throw VolumeError(path + ": a DICOM series UID picks a series in a folder, this is a file");
    }
    if (options.raw) return VolumeFormat::Raw;
    std::string name = std::filesystem::path(path).filename().string();
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
    if (endsWith(name, ".nrrd") || endsWith(name, ".nhdr")) return VolumeFormat::Nrrd;
    if (endsWith(name, ".nii") || endsWith(name, ".nii.gz") || endsWith(name, ".hdr")) return VolumeFormat::Nifti;
    if (endsWith(name, ".mha") || endsWith(name, ".mhd")) return VolumeFormat::MetaImage;
    if (endsWith(name, ".vdb")) return VolumeFormat::Vdb;
    if (endsWith(name, ".raw") || endsWith(name, ".bin")) {
        throw VolumeError(path +
                          ": a raw file needs its description (dims, type, spacing), e.g. "
                          "--raw 512x512x451:int16:0.7x0.7x1.25");
    }
    throw VolumeError(path +
                      ": unknown volume format (expected a DICOM folder, .nrrd, .nhdr, .nii, .nii.gz, "
                      ".mha, .mhd, .vdb, or a raw file with its description)");
}

Volume loadVolume(const std::string& path, const LoadOptions& options) {
    switch (volumeFormatOf(path, options)) {
        case VolumeFormat::DicomSeries: return readDicomSeries(path, options.dicomSeriesUid);
        case VolumeFormat::Nifti: return readNifti(path);
        case VolumeFormat::Nrrd: return readNrrd(path);
        case VolumeFormat::MetaImage: return readMetaImage(path);
        case VolumeFormat::Raw: return readRaw(path, *options.raw);
        case VolumeFormat::Vdb: return readVdb(path);
    }
    throw VolumeError(path + ": unknown volume format");
}

LoadedVolume loadVolumeWithBricks(const std::string& path, const LoadOptions& options) {
    LoadedVolume loaded;
    loaded.format = volumeFormatOf(path, options);
    if (loaded.format == VolumeFormat::Vdb) {
        loaded.volume = readVdb(path, &loaded.bricks);
    } else {
        loaded.volume = loadVolume(path, options);
        loaded.bricks = buildBrickMinMax(loaded.volume);
    }
    return loaded;
}

}  // namespace volumes
