// Tests core/point_kd_tree.* against brute-force nearest-neighbour search.
#include "sdcb/core/sphere/point_kd_tree.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

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

// The direction index gives brute force's answers: unit points spread,
// clustered (a thousand within 0.01 rad, as the fit's knots crowd a
// feature), few, duplicated, and symmetric (the octahedron's vertices, with
// queries at its faces' centres: exact ties); queries on the sphere, longer
// and shorter (down to the 0.5 where the tree takes over, and below), at
// the points themselves and on the cube map's edges and corners.
TEST(PointKdTreeTest, DirectionIndexMatchesBruteForce) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  auto unit = [&] {
    return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
  };
  std::vector<Eigen::MatrixX3d> sets;
  for (int n : {1, 2, 7, 300, 2000}) {
    Eigen::MatrixX3d points(n, 3);
    for (int i = 0; i < n; ++i) points.row(i) = unit().transpose();
    if (n >= 300) points.row(250) = points.row(20);  // a tie: 20 wins
    sets.push_back(points);
  }
  Eigen::MatrixX3d clustered(1100, 3);
  const Eigen::Vector3d centre = unit();
  for (int i = 0; i < 1100; ++i) {
    clustered.row(i) =
        i < 1000 ? (centre + 0.01 * unit()).normalized() : unit();
  }
  sets.push_back(clustered);
  Eigen::MatrixX3d octahedron(6, 3);
  octahedron << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  sets.push_back(octahedron);
  for (const Eigen::MatrixX3d& points : sets) {
    const PointKdTree index(points, true);
    std::vector<Eigen::Vector3d> queries;
    for (int t = 0; t < 3000; ++t) {
      const double length = t % 5 == 0   ? 0.5
                            : t % 7 == 0 ? 0.3
                                         : 0.6 + 0.9 * uniform(rng);
      queries.push_back(length * unit());
    }
    for (Eigen::Index i = 0; i < std::min<Eigen::Index>(points.rows(), 200);
         ++i) {
      queries.push_back(points.row(i).transpose());
      queries.push_back(0.999 * points.row(i).transpose());
    }
    for (int x : {-1, 0, 1}) {
      for (int y : {-1, 0, 1}) {
        for (int z : {-1, 0, 1}) {
          if (x != 0 || y != 0 || z != 0) {
            queries.push_back(Eigen::Vector3d(x, y, z).normalized());
          }
        }
      }
    }
    for (size_t t = 0; t < queries.size(); ++t) {
      const Eigen::Vector3d& q = queries[t];
      const double bound = t % 3 == 0 ? 0.05 : 1e300;
      const auto expected = BruteForce(points, q, bound, -1);
      const auto got = index.NearestNear(q, -1, bound);
      ASSERT_EQ(got.index, expected.index)
          << points.rows() << " points, query " << t;
      ASSERT_EQ(got.squared_distance, expected.squared_distance);
    }
  }
}

}  // namespace
}  // namespace sdcb
