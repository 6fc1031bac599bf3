#include "sdcb/core/spline/knot_hull.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/sphere/perturbed_predicates.h"
#include "testing/random_knots.h"

namespace sdcb {
namespace {

using testing::UniformKnots;

Eigen::MatrixX3d CubeKnots() {
  Eigen::MatrixX3d knots(8, 3);
  int i = 0;
  for (double x : {-1.0, 1.0}) {
    for (double y : {-1.0, 1.0}) {
      for (double z : {-1.0, 1.0}) {
        knots.row(i++) = Eigen::RowVector3d(x, y, z).normalized();
      }
    }
  }
  return knots;
}

// Checks the hull against its definition, facet by facet and knot by knot
// (brute force), and against Euler's formula for a triangulated sphere.
void ExpectValidHull(const Eigen::MatrixX3d& knots) {
  const int n = static_cast<int>(knots.rows());
  const auto hull = ComputeKnotHull(knots);
  ASSERT_TRUE(hull.ok()) << hull.status().message();
  EXPECT_EQ(static_cast<int>(hull->facets.size()), 2 * n - 4);  // V - E + F = 2
  std::map<std::pair<int, int>, int> directed_edges;
  for (const auto& f : hull->facets) {
    for (int q = 0; q < n; ++q) {
      if (q == f[0] || q == f[1] || q == f[2]) continue;
      ASSERT_EQ(PerturbedOrient3dSign(knots, f[0], f[1], f[2], q), -1)
          << "knot " << q << " outside facet " << f[0] << " " << f[1] << " "
          << f[2];
    }
    for (int i = 0; i < 3; ++i) ++directed_edges[{f[i], f[(i + 1) % 3]}];
  }
  // Closed and consistently oriented: each directed edge once, its twin too.
  for (const auto& [edge, count] : directed_edges) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed_edges.count({edge.second, edge.first}), 1u);
  }
  int degree_sum = 0;
  for (int v = 0; v < n; ++v) {
    EXPECT_GE(hull->neighbors[v].size(), 3u);  // every knot is a vertex
    EXPECT_TRUE(
        std::is_sorted(hull->neighbors[v].begin(), hull->neighbors[v].end()));
    for (int w : hull->neighbors[v]) {
      EXPECT_EQ(directed_edges.count({v, w}), 1u);
    }
    degree_sum += static_cast<int>(hull->neighbors[v].size());
  }
  EXPECT_EQ(degree_sum, 2 * (3 * n - 6));
}

TEST(KnotHullTest, RandomKnotsGiveAValidHull) {
  for (int n : {4, 5, 9, 60, 300}) ExpectValidHull(UniformKnots(n, 31 + n));
}

TEST(KnotHullTest, CoCircularKnotsAreTriangulatedUnderThePerturbation) {
  // Each square face of the cube becomes two triangles: 12 facets.
  ExpectValidHull(CubeKnots());
  // Knots only on a hemisphere's rim and one pole: the hull is a cone
  // whose base plane passes through the origin.
  Eigen::MatrixX3d cone(13, 3);
  for (int i = 0; i < 12; ++i) {
    const double a = 2 * kPi * i / 12;
    cone.row(i) << std::cos(a), std::sin(a), 0.0;
  }
  cone.row(12) << 0, 0, 1;
  ExpectValidHull(cone);
}

// The perturbation depends only on the order of the knot indices, so the
// hull of an ascending subset equals the hull of those knots renumbered.
TEST(KnotHullTest, SubsetHullMatchesHullOfTheExtractedKnots) {
  Eigen::MatrixX3d knots(28, 3);
  knots << UniformKnots(20, 8), CubeKnots();  // co-circular knots included
  const std::vector<int> subset = {1, 4, 5, 9, 13, 20, 21, 22, 23, 26, 27};
  Eigen::MatrixX3d extracted(subset.size(), 3);
  for (size_t i = 0; i < subset.size(); ++i)
    extracted.row(i) = knots.row(subset[i]);
  const auto expected = ComputeKnotHull(extracted);
  const auto got = ComputeKnotSubsetHull(knots, subset);
  ASSERT_TRUE(expected.ok() && got.ok());
  std::vector<std::array<int, 3>> mapped;
  for (const auto& f : expected->facets) {
    mapped.push_back({subset[f[0]], subset[f[1]], subset[f[2]]});
  }
  std::sort(mapped.begin(), mapped.end());
  EXPECT_EQ(*got, mapped);
}

TEST(KnotHullTest, IsReproducible) {
  const Eigen::MatrixX3d knots = UniformKnots(500, 2);
  const auto a = ComputeKnotHull(knots);
  const auto b = ComputeKnotHull(knots);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->facets, b->facets);
}

TEST(KnotHullTest, RejectsFewerThanFourKnots) {
  EXPECT_EQ(ComputeKnotHull(UniformKnots(3, 1)).status().code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace sdcb
