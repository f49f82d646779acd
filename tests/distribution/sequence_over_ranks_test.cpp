// The request rank 0 sends every rank of a display render: its text round trip keeps the volume,
// the display and every pose's numbers exactly; with one rank the reading runs once, in place.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "distribution/mpi_session.h"
#include "distribution/sequence_over_ranks.h"
#include "engine/display/display_json.h"

namespace {

distribution::SequenceRequest someRequest() {
    distribution::SequenceRequest request;
    request.volumePath = "/data/ct \"colon\"/ñame.nrrd";  // quotes and non-ASCII survive the JSON
    request.display = engine::loadDisplay("cave4");
    for (int i = 0; i < 5; ++i) {
        const double a = 0.1 + i * std::sqrt(2.0);
        request.poses.push_back({{a * 10.0, -std::exp(a), 1.0 / 3.0 + i},
                                 {std::cos(a), 0.0, std::sin(a)},
                                 {0.0, 1.0, 0.0}});
    }
    return request;
}

TEST(SequenceOverRanks, RequestTextRoundTripIsExact) {
    const distribution::SequenceRequest request = someRequest();
    const distribution::SequenceRequest back =
        distribution::sequenceRequestFromText(distribution::sequenceRequestText(request));
    EXPECT_EQ(back.volumePath, request.volumePath);
    EXPECT_EQ(engine::displayJson(back.display), engine::displayJson(request.display));
    ASSERT_EQ(back.poses.size(), request.poses.size());
    for (std::size_t i = 0; i < request.poses.size(); ++i) {
        EXPECT_EQ(back.poses[i].positionMm, request.poses[i].positionMm) << "pose " << i;
        EXPECT_EQ(back.poses[i].forward, request.poses[i].forward) << "pose " << i;
        EXPECT_EQ(back.poses[i].up, request.poses[i].up) << "pose " << i;
    }
}

TEST(SequenceOverRanks, RequestTextRefusesAnotherMessage) {
    EXPECT_ANY_THROW(distribution::sequenceRequestFromText("{\"volume\": \"a.nrrd\"}"));
    EXPECT_ANY_THROW(distribution::sequenceRequestFromText("not json"));
}

TEST(SequenceOverRanks, OneRankReadsTheRequestOnceInPlace) {
    distribution::MpiSession& session = distribution::mpiSession();
    ASSERT_FALSE(session.isShared());
    int reads = 0;
    const distribution::SequenceRequest request = distribution::sharedSequenceRequest(session, [&] {
        ++reads;
        return someRequest();
    });
    EXPECT_EQ(reads, 1);
    EXPECT_EQ(request.volumePath, someRequest().volumePath);
    EXPECT_EQ(request.poses.size(), 5u);
}

}  // namespace
