// Tests core/point_kd_tree.* against brute-force nearest-neighbour search.
#include "sdcb/core/sphere/point_kd_tree.h"

#include <gtest/gtest.h>

#include <random>

namespace sdcb {
namespace {

PointKdTree::Neighbor BruteForce(const Eigen::MatrixX3d& points,
                                 const Eigen::Vector3d& q, double bound,
                                 int exclude) {
  PointKdTree::Neighbor best;
  for (int i = 0; i < points.rows(); ++i) {
    if (i == exclude) continue;
    const double d = (points.row(i).transpose() - q).squaredNorm();
    if (d < bound && d < best.squared_distance) {  // first of ties wins
      best.index = i;
      best.squared_distance = d;
    }
  }
  return best;
}

TEST(PointKdTreeTest, MatchesBruteForceWithBoundsAndExclusion) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  for (int n : {0, 1, 5, 9, 100, 2000}) {
    Eigen::MatrixX3d points(n, 3);
    for (int i = 0; i < n; ++i) {
      points.row(i) << normal(rng), normal(rng), normal(rng);
    }
    // Duplicates make ties: the smaller index must win.
    if (n >= 100) points.row(77) = points.row(12);
    const PointKdTree tree(points);
    EXPECT_EQ(tree.size(), n);
    for (int t = 0; t < 300; ++t) {
      Eigen::Vector3d q(normal(rng), normal(rng), normal(rng));
      if (n >= 100 && t % 10 == 0) q = points.row(77);
      const double bound = t % 3 == 0 ? 0.25 : 1e300;
      const int exclude = (t % 4 == 0 && n > 0) ? t % n : -1;
      const auto expected = BruteForce(points, q, bound, exclude);
      const auto got = tree.Nearest(q, bound, exclude);
      ASSERT_EQ(got.index, expected.index) << n << " " << t;
      ASSERT_EQ(got.squared_distance, expected.squared_distance);
    }
  }
}

// A hint only tightens the search: with any hint (the answer, a far point,
// one of two tied points, none) the answer is brute force's.
TEST(PointKdTreeTest, NearestNearMatchesBruteForceForAnyHint) {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  const int n = 1000;
  Eigen::MatrixX3d points(n, 3);
  for (int i = 0; i < n; ++i) {
    points.row(i) =
        Eigen::RowVector3d(normal(rng), normal(rng), normal(rng)).normalized();
  }
  points.row(640) = points.row(31);  // a tie: 31 must win, even hinted 640
  const PointKdTree tree(points);
  for (int t = 0; t < 400; ++t) {
    Eigen::Vector3d q(normal(rng), normal(rng), normal(rng));
    q.normalize();
    if (t % 8 == 0) q = points.row(31).transpose() * 1.001;
    const double bound = t % 5 == 0 ? 0.05 : 1e300;
    const auto expected = BruteForce(points, q, bound, -1);
    const int far = (expected.index + n / 2) % n;
    for (int hint : {-1, expected.index, far, 640, t % n}) {
      const auto got = tree.NearestNear(q, hint, bound);
      ASSERT_EQ(got.index, expected.index) << t << " hint " << hint;
      ASSERT_EQ(got.squared_distance, expected.squared_distance);
    }
  }
}

}  // namespace
}  // namespace sdcb
