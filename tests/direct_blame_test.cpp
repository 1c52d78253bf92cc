// Who holds a macro step up on the direct plane, from what the master
// knows (remote::blame()): a node that keeps reporting its steps while it
// withholds its data from a peer is named, not the peer that waits for it
// (the master once took "the peer reported past the claimant" for proof that
// the peer had sent its data, broke ties by load order, and let one node's
// frames extend every node's deadline), in each variant: reports past the
// claimant or held to a tie, a forged counter-claim, three participants,
// a chain of claims, Gauss-Seidel's offset; and a claim the links refute
// still names the claimant.
#include <gtest/gtest.h>

#include "remote/direct_exchange.hpp"

namespace railcosim {
namespace {

using remote::blame;
using remote::HoldUp;
using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

const Clock::time_point t0 = Clock::now();

HoldUp node(std::string role, std::vector<std::string> peers, long reported,
            std::string waiting_for = "", milliseconds claimed = milliseconds(0),
            milliseconds useful = milliseconds(0)) {
  HoldUp h;
  h.role = std::move(role);
  h.peers = std::move(peers);
  h.reported = reported;
  h.waiting_for = std::move(waiting_for);
  h.claimed_at = t0 + claimed;
  h.last_useful = t0 + useful;
  return h;
}

TEST(DirectBlame, AWithholderReportingPastItsClaimantIsNamed) {
  // The vehicle at macro step 5 waits for the track's data; the track's own
  // reports went on to 200.
  const auto b = blame({node("vehicle", {"track"}, 5, "track"), node("track", {"vehicle"}, 200)});
  EXPECT_EQ(b.node, 1u);
  EXPECT_EQ(b.claim, "");
  // Loaded the other way round, the same.
  EXPECT_EQ(blame({node("track", {"vehicle"}, 200), node("vehicle", {"track"}, 5, "track")}).node,
            0u);
}

TEST(DirectBlame, AWithholderWhoseReportsAreHeldToATieIsNamed) {
  EXPECT_EQ(blame({node("vehicle", {"track"}, 5, "track"), node("track", {"vehicle"}, 5)}).node,
            1u);
  // Its reports one behind the claimant's (Gauss-Seidel's order): the same.
  EXPECT_EQ(blame({node("vehicle", {"track"}, 5, "track"), node("track", {"vehicle"}, 4)}).node,
            1u);
}

TEST(DirectBlame, AForgedCounterClaimDoesNotShiftTheBlame) {
  // The track says, later, that it waits for the vehicle: ahead of it...
  EXPECT_EQ(blame({node("vehicle", {"track"}, 5, "track", milliseconds(10)),
                   node("track", {"vehicle"}, 200, "vehicle", milliseconds(40))})
                .node,
            1u);
  // ... on a tie, and one step ahead (Gauss-Seidel's track steps first).
  EXPECT_EQ(blame({node("vehicle", {"track"}, 5, "track", milliseconds(10)),
                   node("track", {"vehicle"}, 5, "vehicle", milliseconds(40))})
                .node,
            1u);
  EXPECT_EQ(blame({node("vehicle", {"track"}, 5, "track", milliseconds(10)),
                   node("track", {"vehicle"}, 6, "vehicle", milliseconds(40))})
                .node,
            1u);
}

TEST(DirectBlame, ThreeParticipantsNameTheWithholder) {
  // vehicle | track | soil: the track withholds from the vehicle, the soil
  // has what it needs (it reported the step).
  HoldUp soil = node("soil", {"track"}, 199);
  soil.has_step = true;
  EXPECT_EQ(
      blame({node("vehicle", {"track"}, 5, "track"), node("track", {"vehicle", "soil"}, 200), soil})
          .node,
      1u);
  // The soil withholds from the track, which waits for it, and the vehicle
  // waits for the track: the end of the chain, whatever the soil reported.
  EXPECT_EQ(blame({node("vehicle", {"track"}, 5, "track", milliseconds(30)),
                   node("track", {"vehicle", "soil"}, 5, "soil", milliseconds(10)),
                   node("soil", {"track"}, 200)})
                .node,
            2u);
}

TEST(DirectBlame, AClaimTheLinksRefuteNamesTheClaimant) {
  const auto b = blame({node("vehicle", {"track"}, 5, "soil"),
                        node("track", {"vehicle", "soil"}, 6), node("soil", {"track"}, 200)});
  EXPECT_EQ(b.node, 0u);
  EXPECT_EQ(b.claim, "; it says it waits for the soil participant, with which it has no peer link");
  const auto c = blame({node("vehicle", {"track"}, 5, "rail"), node("track", {"vehicle"}, 6)});
  EXPECT_EQ(c.node, 0u);
  EXPECT_EQ(c.claim,
            "; it says it waits for the rail participant, which is not a participant of "
            "this run");
  // Itself.
  EXPECT_EQ(blame({node("vehicle", {"track"}, 5, "vehicle"), node("track", {"vehicle"}, 6)}).node,
            0u);
}

TEST(DirectBlame, WithoutClaimsTheNodeSilentLongestIsNamedNotTheFirstLoaded) {
  // Both at macro step 5; the track's last useful frame is older.
  EXPECT_EQ(blame({node("vehicle", {"track"}, 5, "", {}, milliseconds(900)),
                   node("track", {"vehicle"}, 5, "", {}, milliseconds(100))})
                .node,
            1u);
  // One that has reported the step waited for is not named, however long
  // it has been silent since.
  HoldUp ahead = node("vehicle", {"track"}, 200, "", {}, milliseconds(0));
  ahead.has_step = true;
  EXPECT_EQ(blame({ahead, node("track", {"vehicle"}, 5, "", {}, milliseconds(900))}).node, 1u);
}

}  // namespace
}  // namespace railcosim
