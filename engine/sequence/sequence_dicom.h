/// @brief A finished sequence folder's pictures as DICOM for PACS: per frame, one Secondary
/// Capture series per eye (its walls) and one for the review sheet (and before/after where it
/// was written), each carrying the source series' patient and study.
#pragma once

#include <string>
#include <vector>

#include "engine/sequence/frame_sequence.h"
#include "volumes/dicom_secondary_capture.h"

namespace engine {

/// What writeSequenceDicom wrote.
struct SequenceDicomSummary {
    int files = 0;
    int series = 0;
};

/// Reads each PNG of `job`'s frames in `sequenceFolder` (both eyes' walls, the sheet,
/// before_after.png where asked for) and writes it into `dicomFolder` as
/// frame_NNNN_EYE_WALL.dcm, frame_NNNN_sheet.dcm and frame_NNNN_before_after.dcm. The series
/// descriptions name the display, the frame and the eye. Throws std::runtime_error naming the
/// file when a picture is missing, a DICOM file exists and `force` is false, or a write fails.
SequenceDicomSummary writeSequenceDicom(const SequenceJob& job, const std::string& sequenceFolder,
                                        const std::string& dicomFolder, const volumes::DicomIdentifiers& identifiers,
                                        bool force);

}  // namespace engine
