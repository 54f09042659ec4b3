#include "common/shepherd/worldmodel/associator.h"

#include <gtest/gtest.h>

namespace ephor::worldmodel {
namespace {

TEST(AssociatorTest, EachObjectTakesTheBlobNearestItsPrediction) {
  // Two objects whose blobs came out of the blobifier in swapped order
  // (paper figure 15): the mapping follows position, not order.
  const std::vector<GatedPrediction> objects = {{{100, 100}, 5}, {{100, 110}, 5}};
  const std::vector<Eigen::Vector2d> blobs = {{100.5, 110.2}, {99.8, 100.3}};
  const auto m = Associator::assign(objects, blobs);
  ASSERT_EQ(m.size(), 2u);
  for (const auto& a : m) EXPECT_EQ(a.blob, a.object == 0 ? 1u : 0u);
}

TEST(AssociatorTest, BlobsOutsideTheGateOrAlreadyTakenAreNotOffered) {
  const std::vector<GatedPrediction> objects = {{{100, 100}, 5}};
  EXPECT_TRUE(Associator::assign(objects, {{106, 100}}).empty());
  EXPECT_TRUE(Associator::assign(objects, {{101, 100}}, {true}).empty());
  EXPECT_EQ(Associator::assign(objects, {{101, 100}}, {false}).size(), 1u);
}

TEST(AssociatorTest, AContestedBlobGoesToTheMoreLikelyObjectNotTheWiderGate) {
  // Issue 13, a recorded run: a sheep nudged by the arm jumps 7.6 px; its
  // object, hidden one frame, has a 10.7 px gate; another object hidden 12 s
  // (gate 120 px) was reckoned 55 px away. 55 / 120 < 7.6 / 10.7, but the
  // blob is far likelier from the first.
  const std::vector<GatedPrediction> objects = {{{0, 55}, 120}, {{7.6, 0}, 10.7}};
  const auto m = Associator::assign(objects, {{0, 0}});
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].object, 1u);
}

TEST(AssociatorTest, AmongEqualGatesTheNearestWins) {
  const std::vector<GatedPrediction> objects = {{{94, 100}, 20}, {{103, 100}, 20}, {{90, 100}, 20}};
  const auto m = Associator::assign(objects, {{100, 100}});
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].object, 1u);
}

TEST(AssociatorTest, AHiddenObjectMayBeAnywhereBetweenWhereItWasSeenAndWhereItIsReckoned) {
  // Issue 13, a recorded run: sheep A was last seen at (0, 0) and reckoned on
  // to (0, 60); sheep B last seen at (100, 0), reckoned to (60, 0). A blob at
  // (0, -40) is A turned back (40 px from A's path, 72 from B's reckoning).
  const std::vector<GatedPrediction> objects = {{{0, 60}, 120, {0, 0}}, {{60, 0}, 120, {100, 0}}};
  const auto m = Associator::assign(objects, {{0, -40}});
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].object, 0u);
  EXPECT_NEAR(m[0].distance_px, 40.0, 1e-9);
  // Without the path, the reckoned points alone give the blob to B (72 < 100).
  const auto points = Associator::assign({{{0, 60}, 120}, {{60, 0}, 120}}, {{0, -40}});
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(points[0].object, 1u);
}

}  // namespace
}  // namespace ephor::worldmodel
