#include "procs/stripe/range/cloud_accumulator.h"

#include <gtest/gtest.h>

namespace ephor::stripe {
namespace {

std::vector<Eigen::Vector3d> pts(double x, int n) {
  std::vector<Eigen::Vector3d> v;
  for (int i = 0; i < n; ++i) v.emplace_back(x, i, 0);
  return v;
}

TEST(CloudAccumulator, CompleteInStripeOrderOnceEveryCapturedStripeIsHeard) {
  CloudAccumulator a;
  EXPECT_TRUE(a.add(7, 2, pts(2, 3)));
  EXPECT_TRUE(a.add(7, 0, pts(0, 2)));
  EXPECT_FALSE(a.add(7, 0, pts(9, 5))) << "a repeat";
  EXPECT_FALSE(a.add(0, 1, pts(9, 5))) << "not a scan";
  a.captured(7, 3, 1.0);
  EXPECT_TRUE(a.take_complete(1.5).empty()) << "stripe 1 not heard yet";
  EXPECT_TRUE(a.add(7, 1, pts(1, 1)));
  const auto done = a.take_complete(1.6);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].stripes, 3);
  EXPECT_EQ(done[0].stripes_missing, 0);
  ASSERT_EQ(done[0].points.size(), 6u);
  EXPECT_EQ(done[0].points[0].x(), 0);
  EXPECT_EQ(done[0].points[2].x(), 1);
  EXPECT_EQ(done[0].points[5].x(), 2);
  EXPECT_TRUE(a.finished(7));
  EXPECT_FALSE(a.add(7, 3, pts(3, 1))) << "late";
  EXPECT_TRUE(a.take_complete(2.0).empty()) << "given once";
}

TEST(CloudAccumulator, MissingStripesAreGivenUpAfterTheTimeout) {
  CloudAccumulator a(2.0);
  a.add(5, 0, pts(0, 4));
  a.captured(5, 2, 10.0);
  EXPECT_TRUE(a.take_complete(11.9).empty());
  const auto done = a.take_complete(12.0);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].stripes_missing, 1);
  EXPECT_EQ(done[0].points.size(), 4u);
}

}  // namespace
}  // namespace ephor::stripe
