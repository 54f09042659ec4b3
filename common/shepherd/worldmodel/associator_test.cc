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

TEST(AssociatorTest, TheTighterRelativeMatchWinsAContestedBlob) {
  // Blob 6 px from a (gate 20) and 3 px from b (gate 4): 0.3 vs 0.75 of the
  // gate, so a gets it and b, with nothing else in its gate, gets nothing.
  const std::vector<GatedPrediction> objects = {{{94, 100}, 20}, {{103, 100}, 4}};
  const auto m = Associator::assign(objects, {{100, 100}});
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].object, 0u);
}

}  // namespace
}  // namespace ephor::worldmodel
