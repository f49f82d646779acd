/// @brief A display render's frame sequence shared over the ranks of a run (one process: all of
/// it, on the same code path): rank 0 reads the request (volume, display, poses) and sends it to
/// every rank, the frames or walls are dealt out, and under mpirun rank 0 names a rank that dies,
/// and the frame it was at, when mpirun stops the job.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "distribution/mpi_session.h"
#include "engine/display/display.h"
#include "engine/render/camera_pose.h"
#include "engine/render/raycaster.h"
#include "engine/sequence/frame_sequence.h"

namespace distribution {

/// What rank 0 reads and works out for every rank: the volume to render (the cleansed one after
/// `--path auto`), the display and the poses.
struct SequenceRequest {
    std::string volumePath;
    engine::Display display;
    std::vector<engine::CameraPose> poses;
};

/// The request as one text (JSON) and back: the message rank 0 broadcasts. The round trip keeps
/// the display as displayJson writes it and every pose's numbers exactly.
std::string sequenceRequestText(const SequenceRequest& request);
SequenceRequest sequenceRequestFromText(const std::string& text);

/// Runs `readOnRoot` on rank 0 alone (it may run the colon analysis, write files, throw) and
/// gives every rank its result.
SequenceRequest sharedSequenceRequest(MpiSession& session, const std::function<SequenceRequest()>& readOnRoot);

/// Renders this rank's share of `job` under `distribution` (engine::renderSequence with the
/// session's rank, barrier and messages to rank 0). Under mpirun, rank 0 also arms the stop
/// report for the frames each rank is given (chained after hooks.onPendingFrames).
engine::SequenceSummary renderSequenceOverRanks(MpiSession& session, engine::Raycaster& raycaster,
                                                const engine::SequenceJob& job, const engine::SequenceOutput& output,
                                                engine::SequenceHooks hooks, engine::Distribution distribution);

}  // namespace distribution
