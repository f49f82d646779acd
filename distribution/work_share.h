/// @brief How a job's work is shared over the ranks of one run, the same code path for one rank
/// or many: deal the items out, let rank 0 go first where it fills a cache, gather the results
/// on rank 0, and let rank 0 alone report. With one rank every call is the plain loop.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "distribution/mpi_session.h"

namespace distribution {

/// The positions 0 .. count - 1 that `rank` of `ranks` takes: rank, rank + ranks, ... (every
/// position for one rank). Throws std::invalid_argument for a negative count or a rank outside
/// [0, ranks).
std::vector<int> deal(int count, int rank, int ranks);

/// The items of `items` at this session's dealt positions, in order.
template <class Item>
std::vector<Item> dealt(const std::vector<Item>& items, const MpiSession& session) {
    std::vector<Item> mine;
    for (int position : deal(static_cast<int>(items.size()), session.rank(), session.ranks())) {
        mine.push_back(items[static_cast<std::size_t>(position)]);
    }
    return mine;
}

/// Runs `work` on rank 0, then, once it is done there, on every other rank: for work that fills a
/// cache on disk (a baked map) the others then read instead of making it again.
void rootFirst(MpiSession& session, const std::function<void()>& work);

/// Every rank's `text` on rank 0, in rank order, once every rank has sent it (the others get an
/// empty list).
std::vector<std::string> gatherAtRoot(MpiSession& session, const std::string& text);

/// Whether this rank speaks for the job (progress, summaries, the review page): rank 0.
inline bool isReporter(const MpiSession& session) { return session.rank() == 0; }

}  // namespace distribution
