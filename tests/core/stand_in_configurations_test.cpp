// STAND-IN: checks the stand-in ComputeDelaunayConfigurations (neighbour
// path, n > 60) against the brute-force oracle. Dropped with the stand-in.
#include <gtest/gtest.h>

#include <random>

#include "core/brute_force_configurations.h"
#include "core/delaunay_configurations.h"

namespace sdcb {
namespace {

TEST(StandInConfigurations, NeighbourSearchEqualsBruteForce) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  Eigen::MatrixX3d knots(90, 3);
  for (int i = 0; i < knots.rows(); ++i) {
    knots.row(i) =
        Eigen::RowVector3d(normal(rng), normal(rng), normal(rng)).normalized();
  }
  for (int degree : {0, 2, 4}) {
    auto fast = ComputeDelaunayConfigurations(knots, degree);
    ASSERT_TRUE(fast.ok()) << fast.status().message();
    const DelaunayConfigurations slow =
        testing::BruteForceConfigurations(knots, degree);
    ASSERT_EQ(fast->sets.size(), slow.sets.size());
    for (size_t i = 0; i < slow.sets.size(); ++i) {
      EXPECT_EQ(fast->sets[i].knots, slow.sets[i].knots);
      EXPECT_EQ(fast->sets[i].boundaries, slow.sets[i].boundaries);
    }
  }
}

}  // namespace
}  // namespace sdcb
