// The sample lattices (core/measure/sample_lattice.h): point and triangle
// counts, barycentric weights that sum to one, triangles that tile the
// triangle (or the square) once with one orientation, and every edge once
// among the upward triangles.
#include "sdcb/core/measure/sample_lattice.h"

#include <gtest/gtest.h>

#include <set>
#include <utility>

namespace sdcb {
namespace {

// Twice the signed area of triangle t in the (i, j) plane (or the (j, i)
// plane with `transposed`).
int TwiceArea(const std::vector<Eigen::Vector2i>& points,
              const Eigen::Vector3i& t, bool transposed) {
  Eigen::Vector2i p[3];
  for (int k = 0; k < 3; ++k) {
    p[k] = transposed ? Eigen::Vector2i(points[t[k]][1], points[t[k]][0])
                      : points[t[k]];
  }
  const Eigen::Vector2i e0 = p[1] - p[0], e1 = p[2] - p[0];
  return e0[0] * e1[1] - e0[1] * e1[0];
}

TEST(SampleLatticeTest, TriangleLatticeCountsWeightsAndTiling) {
  for (const LatticeOrientation orientation :
       {LatticeOrientation::kIJ, LatticeOrientation::kJI}) {
    for (int n = 1; n <= 12; ++n) {
      const TriangleLattice l(n, orientation);
      ASSERT_EQ(static_cast<int>(l.points.size()), (n + 1) * (n + 2) / 2);
      ASSERT_EQ(TriangleLattice::NumPoints(n), (n + 1) * (n + 2) / 2);
      ASSERT_EQ(static_cast<int>(l.triangles.size()), n * n);
      ASSERT_EQ(l.upward.size(), l.triangles.size());
      for (size_t k = 0; k < l.points.size(); ++k) {
        const int i = l.points[k][0], j = l.points[k][1];
        EXPECT_EQ(l.Index(i, j), static_cast<int>(k));
        EXPECT_GE(i, 0);
        EXPECT_GE(j, 0);
        EXPECT_LE(i + j, n);
        // The barycentric weights i / n, j / n, (n - i - j) / n sum to 1.
        EXPECT_DOUBLE_EQ(double(i) / n + double(j) / n + double(n - i - j) / n,
                         1.0);
      }
      // Every triangle has area 1/2 in lattice units, counter-clockwise in
      // its plane: n^2 of them tile the triangle of area n^2 / 2.
      int upward = 0;
      std::set<std::pair<int, int>> edges;
      for (size_t t = 0; t < l.triangles.size(); ++t) {
        EXPECT_EQ(TwiceArea(l.points, l.triangles[t],
                            orientation == LatticeOrientation::kJI),
                  1);
        if (!l.upward[t]) continue;
        ++upward;
        for (int k = 0; k < 3; ++k) {
          const int a = l.triangles[t][k], b = l.triangles[t][(k + 1) % 3];
          EXPECT_TRUE(edges.emplace(std::min(a, b), std::max(a, b)).second);
        }
      }
      EXPECT_EQ(upward, n * (n + 1) / 2);
      // 3 n (n + 1) / 2 edges in the lattice, each in one upward triangle.
      EXPECT_EQ(static_cast<int>(edges.size()), 3 * n * (n + 1) / 2);
    }
  }
}

TEST(SampleLatticeTest, BothOrientationsListTheSameTrianglesInOneOrder) {
  const TriangleLattice ij(5, LatticeOrientation::kIJ);
  const TriangleLattice ji(5, LatticeOrientation::kJI);
  ASSERT_EQ(ij.points, ji.points);
  ASSERT_EQ(ij.upward, ji.upward);
  for (size_t t = 0; t < ij.triangles.size(); ++t) {
    std::set<int> a(ij.triangles[t].data(), ij.triangles[t].data() + 3);
    std::set<int> b(ji.triangles[t].data(), ji.triangles[t].data() + 3);
    EXPECT_EQ(a, b);
  }
}

TEST(SampleLatticeTest, SquareLatticeCountsAndTiling) {
  for (int n = 1; n <= 8; ++n) {
    const SquareLattice l(n);
    ASSERT_EQ(static_cast<int>(l.points.size()), (n + 1) * (n + 1));
    ASSERT_EQ(SquareLattice::NumPoints(n), (n + 1) * (n + 1));
    ASSERT_EQ(static_cast<int>(l.triangles.size()), 2 * n * n);
    for (size_t k = 0; k < l.points.size(); ++k) {
      EXPECT_EQ(l.points[k][0] * (n + 1) + l.points[k][1], static_cast<int>(k));
    }
    for (const Eigen::Vector3i& t : l.triangles) {
      EXPECT_EQ(TwiceArea(l.points, t, /*transposed=*/true), 1);
    }
  }
}

}  // namespace
}  // namespace sdcb
