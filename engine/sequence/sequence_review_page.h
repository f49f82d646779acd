/// @brief The review page of a rendered sequence folder: its frames, poses and images as
/// renderSequence names them, and the job's display, map, rendering and volume as facts.
#pragma once

#include "engine/review/review_page.h"
#include "engine/sequence/frame_sequence.h"
#include "volumes/volume.h"

namespace engine {

/// The page of a finished sequence folder: its frames and poses from `job`, the images named as
/// renderSequence names them (both eyes' walls, the sheet, before/after where asked for), the
/// job's display, map and volume as facts.
ReviewPage reviewPageOfSequence(const SequenceJob& job, const volumes::Volume* ct);

}  // namespace engine
