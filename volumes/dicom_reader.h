/// @brief DICOM CT series reading through GDCM: one folder, one series, slices ordered by
/// their position along the slice normal, pixel values rescaled to HU.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "volumes/volume.h"

namespace volumes {

/// One series found in a folder.
struct DicomSeriesInfo {
    std::string seriesUid;  ///< SeriesInstanceUID (0020,000E)
    std::size_t fileCount = 0;
};

/// Lists the image series in `folder` (searched recursively), largest first. Files that are
/// not DICOM images with a position and orientation are ignored. Throws VolumeError when the
/// folder is missing or holds no such file.
std::vector<DicomSeriesInfo> listDicomSeries(const std::string& folder);

/// Reads one CT series from `folder` (recursively): the one whose SeriesInstanceUID is
/// `seriesUid`, or the largest when `seriesUid` is empty (several equally large series are an
/// error that lists them). Slices are sorted by ImagePositionPatient projected on the normal
/// row x column of ImageOrientationPatient, so the volume's z axis is that normal, and its
/// spacing the distance between slice positions. Any transfer syntax GDCM decodes is accepted
/// (raw, JPEG lossless, JPEG 2000, JPEG-LS, RLE, deflate). HU = stored * RescaleSlope +
/// RescaleIntercept per slice. Gantry tilt, uneven or duplicate slice positions, differing
/// orientation, sizes or pixel spacing across slices are refused with a VolumeError saying
/// which files and values disagree (resample such series with a dedicated tool first), and so
/// are multi-frame (enhanced) files.
Volume readDicomSeries(const std::string& folder, const std::string& seriesUid = {});

}  // namespace volumes
