#include "distribution/work_share.h"

#include <stdexcept>

namespace distribution {

std::vector<int> deal(int count, int rank, int ranks) {
    if (count < 0 || ranks < 1 || rank < 0 || rank >= ranks) {
        throw std::invalid_argument("deal: " + std::to_string(count) + " items to rank " + std::to_string(rank) +
                                    " of " + std::to_string(ranks));
    }
    std::vector<int> positions;
    for (int position = rank; position < count; position += ranks) positions.push_back(position);
    return positions;
}

void rootFirst(MpiSession& session, const std::function<void()>& work) {
    if (session.rank() == 0) work();
    session.barrier();
    if (session.rank() != 0) work();
}

std::vector<std::string> gatherAtRoot(MpiSession& session, const std::string& text) {
    std::vector<std::string> all = session.gather(text);
    session.barrier();
    return all;
}

}  // namespace distribution
