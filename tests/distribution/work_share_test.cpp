// How work is dealt out over ranks: every position to exactly one rank, in order, and one rank
// doing the whole job as the plain loop would.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "distribution/mpi_session.h"
#include "distribution/work_share.h"

namespace {

using distribution::deal;

TEST(WorkShare, DealGivesEveryPositionToExactlyOneRankInOrder) {
    for (int ranks = 1; ranks <= 5; ++ranks) {
        for (int count : {0, 1, 4, 7, 13}) {
            std::vector<int> seen;
            for (int rank = 0; rank < ranks; ++rank) {
                const std::vector<int> mine = deal(count, rank, ranks);
                EXPECT_TRUE(std::is_sorted(mine.begin(), mine.end()));
                for (int position : mine) EXPECT_EQ(position % ranks, rank) << "count " << count << " ranks " << ranks;
                seen.insert(seen.end(), mine.begin(), mine.end());
            }
            std::sort(seen.begin(), seen.end());
            std::vector<int> all(static_cast<std::size_t>(count));
            for (int i = 0; i < count; ++i) all[static_cast<std::size_t>(i)] = i;
            EXPECT_EQ(seen, all) << "count " << count << " ranks " << ranks;
        }
    }
}

TEST(WorkShare, DealRefusesWhatNoRunHas) {
    EXPECT_THROW(deal(-1, 0, 1), std::invalid_argument);
    EXPECT_THROW(deal(3, 2, 2), std::invalid_argument);
    EXPECT_THROW(deal(3, -1, 2), std::invalid_argument);
    EXPECT_THROW(deal(3, 0, 0), std::invalid_argument);
}

TEST(WorkShare, OneRankIsThePlainLoop) {
    distribution::MpiSession session;  // no mpirun: rank 0 of 1
    const std::vector<std::string> items = {"a", "b", "c"};
    EXPECT_EQ(distribution::dealt(items, session), items);
    int runs = 0;
    distribution::rootFirst(session, [&runs] { ++runs; });
    EXPECT_EQ(runs, 1);
    EXPECT_EQ(distribution::gatherAtRoot(session, "mine"), std::vector<std::string>{"mine"});
    EXPECT_TRUE(distribution::isReporter(session));
}

}  // namespace
