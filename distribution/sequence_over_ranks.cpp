#include "distribution/sequence_over_ranks.h"

#include <optional>
#include <utility>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "distribution/rank_stop_report.h"
#include "engine/display/display_json.h"

namespace distribution {

std::string sequenceRequestText(const SequenceRequest& request) {
    nlohmann::json poses = nlohmann::json::array();
    for (const auto& pose : request.poses) {
        poses.push_back({pose.positionMm.x, pose.positionMm.y, pose.positionMm.z, pose.forward.x, pose.forward.y,
                         pose.forward.z, pose.up.x, pose.up.y, pose.up.z});
    }
    return nlohmann::json{{"volume", request.volumePath},
                          {"display", engine::displayJson(request.display)},
                          {"poses", poses}}
        .dump();
}

SequenceRequest sequenceRequestFromText(const std::string& text) {
    const nlohmann::json document = nlohmann::json::parse(text);
    SequenceRequest request;
    request.volumePath = document.at("volume").get<std::string>();
    request.display = engine::displayFromJsonText(document.at("display").get<std::string>());
    for (const auto& p : document.at("poses")) {
        request.poses.push_back({{p[0], p[1], p[2]}, {p[3], p[4], p[5]}, {p[6], p[7], p[8]}});
    }
    return request;
}

SequenceRequest sharedSequenceRequest(MpiSession& session, const std::function<SequenceRequest()>& readOnRoot) {
    SequenceRequest request;
    if (session.rank() == 0) request = readOnRoot();
    if (!session.isShared()) return request;
    return sequenceRequestFromText(session.broadcast(session.rank() == 0 ? sequenceRequestText(request) : std::string()));
}

engine::SequenceSummary renderSequenceOverRanks(MpiSession& session, engine::Raycaster& raycaster,
                                                const engine::SequenceJob& job, const engine::SequenceOutput& output,
                                                engine::SequenceHooks hooks, engine::Distribution distribution) {
    engine::SequenceShare share;
    share.rank = session.rank();
    share.ranks = session.ranks();
    share.distribution = distribution;
    share.barrier = [&session] { session.barrier(); };
    share.reportFrameWritten = [&session](std::vector<unsigned char> message) { session.sendToRoot(std::move(message)); };
    share.takeFrameWritten = [&session] { return session.receiveAtRoot(); };
    // Every rank takes part in the gather; rank 0 alone reports.
    const std::vector<RankProcess> processes =
        session.isShared() ? rankProcessesOf(session.gatherProcesses()) : std::vector<RankProcess>{};
    std::optional<RankStopReport> stopReport;
    if (session.isShared() && session.rank() == 0) {
        stopReport.emplace(isatty(fileno(stderr)) != 0);
        hooks.onPendingFrames = [&, given = std::move(hooks.onPendingFrames)](const std::vector<int>& pending) {
            if (given) given(pending);
            std::vector<std::vector<int>> frames;
            for (int rank = 0; rank < share.ranks; ++rank) frames.push_back(engine::framesOfRank(pending, share, rank));
            stopReport->arm(rankStopStateOf(output.folder, thisHostName(), processes, std::move(frames),
                                            static_cast<int>(job.poses.size())));
        };
    }
    return engine::renderSequence(raycaster, job, output, hooks, share);
}

}  // namespace distribution
