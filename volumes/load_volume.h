/// @brief One entry point that loads any supported CT format, chosen by extension or folder.
#pragma once

#include <optional>
#include <string>

#include "volumes/brick_minmax.h"
#include "volumes/raw_reader.h"
#include "volumes/volume.h"

namespace volumes {

/// The formats loadVolume reads.
enum class VolumeFormat { DicomSeries, Nifti, Nrrd, MetaImage, Raw, Vdb };

/// Human-readable name of `format` ("DICOM series", "NIfTI", ...).
std::string volumeFormatName(VolumeFormat format);

/// What a file name cannot say.
struct LoadOptions {
    /// Required for headerless raw files (.raw, .bin, .img without .hdr); see parseRawSpec.
    std::optional<RawOptions> raw;
    /// DICOM folders: the series to read; empty reads the largest.
    std::string dicomSeriesUid;
};

/// The format loadVolume would use for `path`: a folder is a DICOM series; otherwise the
/// extension decides (.nrrd/.nhdr, .nii/.nii.gz/.hdr, .mha/.mhd, .vdb, .raw/.bin or any file
/// when options.raw is set). Throws VolumeError naming the path for anything else.
VolumeFormat volumeFormatOf(const std::string& path, const LoadOptions& options = {});

/// Loads a CT volume in int16 HU with its LPS geometry. Throws VolumeError (file and problem)
/// for a missing, unsupported, inconsistent or corrupt input; never exits.
Volume loadVolume(const std::string& path, const LoadOptions& options = {});

/// A volume and the brick min/max the renderer skips empty space with.
struct LoadedVolume {
    Volume volume;
    BrickMinMax bricks;
    VolumeFormat format = VolumeFormat::Nrrd;
};

/// loadVolume plus brick min/max, built from the tree's leaves for .vdb files and from the
/// voxels otherwise.
LoadedVolume loadVolumeWithBricks(const std::string& path, const LoadOptions& options = {});

}  // namespace volumes
