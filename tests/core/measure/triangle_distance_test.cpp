// Point-triangle closest points, distances and barycentric coordinates
// (core/measure/triangle_distance.h) against closed forms: the distance to a
// vertex, to an edge's line and to the plane in each Voronoi region of a
// right triangle, and coordinates that rebuild the point.
#include "sdcb/core/measure/triangle_distance.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

namespace sdcb {
namespace {

// The right triangle (0,0,0), (1,0,0), (0,1,0) in the plane z = 0.
const Eigen::Vector3d kA(0, 0, 0), kB(1, 0, 0), kC(0, 1, 0);

TEST(TriangleDistanceTest, FaceRegionIsTheDistanceToThePlane) {
  const Eigen::Vector3d p(0.2, 0.3, -0.7);
  EXPECT_TRUE(ClosestPointOnTriangle(p, kA, kB, kC)
                  .isApprox(Eigen::Vector3d(0.2, 0.3, 0), 1e-14));
  EXPECT_NEAR(PointTriangleDistance(p, kA, kB, kC), 0.7, 1e-14);
}

TEST(TriangleDistanceTest, VertexRegionsAreTheDistanceToTheVertex) {
  // Beyond each corner, outside both edges' slabs.
  const Eigen::Vector3d pa(-0.5, -0.25, 0.5), pb(1.5, -0.5, 0.25),
      pc(-0.25, 1.75, -1.0);
  EXPECT_NEAR(PointTriangleDistance(pa, kA, kB, kC), (pa - kA).norm(), 1e-14);
  EXPECT_NEAR(PointTriangleDistance(pb, kA, kB, kC), (pb - kB).norm(), 1e-14);
  EXPECT_NEAR(PointTriangleDistance(pc, kA, kB, kC), (pc - kC).norm(), 1e-14);
  EXPECT_TRUE(ClosestPointOnTriangle(pb, kA, kB, kC).isApprox(kB, 1e-14));
}

TEST(TriangleDistanceTest, EdgeRegionsAreTheDistanceToTheEdgesLine) {
  // Below AB: the distance to the x axis, sqrt(y^2 + z^2).
  const Eigen::Vector3d p_ab(0.4, -0.3, 0.4);
  EXPECT_NEAR(PointTriangleDistance(p_ab, kA, kB, kC), 0.5, 1e-14);
  // Left of AC: sqrt(x^2 + z^2).
  const Eigen::Vector3d p_ac(-0.6, 0.5, 0.8);
  EXPECT_NEAR(PointTriangleDistance(p_ac, kA, kB, kC), 1.0, 1e-14);
  // Beyond BC (x + y = 1): |x + y - 1| / sqrt(2) in the plane, with z.
  const Eigen::Vector3d p_bc(0.75, 0.75, 0.5);
  const double in_plane = 0.5 / std::sqrt(2.0);
  EXPECT_NEAR(PointTriangleDistance(p_bc, kA, kB, kC),
              std::sqrt(in_plane * in_plane + 0.25), 1e-14);
  EXPECT_TRUE(ClosestPointOnTriangle(p_bc, kA, kB, kC)
                  .isApprox(Eigen::Vector3d(0.5, 0.5, 0), 1e-14));
}

TEST(TriangleDistanceTest, DegenerateTrianglesAreTheirSegments) {
  // Collinear corners: the closest point of the segment from a to c.
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);
  EXPECT_NEAR(PointTriangleDistance(Eigen::Vector3d(1.5, 1, 0), a, b, c), 1.0,
              1e-14);
  EXPECT_NEAR(PointTriangleDistance(Eigen::Vector3d(3, 0, 0), a, b, c), 1.0,
              1e-14);
  // Three coincident corners: the distance to the point.
  EXPECT_NEAR(PointTriangleDistance(Eigen::Vector3d(0, 3, 4), a, a, a), 5.0,
              1e-14);
}

TEST(TriangleDistanceTest, NeverFartherThanAnySampledPointOfTheTriangle) {
  // Brute force over a dense lattice of the triangle: the closest point's
  // distance is at most every lattice point's and within the lattice
  // spacing of the smallest.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Vector3d a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)),
        c(u(rng), u(rng), u(rng)), p(u(rng), u(rng), u(rng));
    const double d = PointTriangleDistance(p, a, b, c);
    const int n = 200;
    double brute = 1e300;
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; i + j <= n; ++j) {
        const double wb = double(i) / n, wc = double(j) / n;
        const Eigen::Vector3d q = (1 - wb - wc) * a + wb * b + wc * c;
        brute = std::min(brute, (p - q).norm());
      }
    }
    const double spacing =
        std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()}) / n;
    EXPECT_LE(d, brute + 1e-12);
    EXPECT_GE(d, brute - spacing);
  }
}

TEST(TriangleCoordinatesTest, RebuildThePointAndSumToOne) {
  const Eigen::Vector3d a(0.3, -1, 2), b(2, 0.5, 1), c(-1, 1, 0.25);
  for (const Eigen::Vector3d w :
       {Eigen::Vector3d(0.2, 0.3, 0.5), Eigen::Vector3d(1, 0, 0),
        Eigen::Vector3d(-0.5, 1.25, 0.25)}) {
    const Eigen::Vector3d q = w[0] * a + w[1] * b + w[2] * c;
    const Eigen::Vector3d got = TriangleCoordinates(q, a, b, c);
    EXPECT_TRUE(got.isApprox(w, 1e-12)) << got.transpose();
    EXPECT_NEAR(got.sum(), 1.0, 1e-14);
  }
  // Off the plane: the coordinates of the projection.
  const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
  const Eigen::Vector3d inside = 0.25 * a + 0.25 * b + 0.5 * c;
  EXPECT_TRUE(TriangleCoordinates(inside + 0.7 * n, a, b, c)
                  .isApprox(Eigen::Vector3d(0.25, 0.25, 0.5), 1e-12));
}

TEST(TriangleCoordinatesTest, ClampedOnesArePointsOfTheTriangle) {
  const Eigen::Vector3d outside = 1.2 * kB - 0.1 * kA - 0.1 * kC;
  const Eigen::Vector3d w = ClampedTriangleCoordinates(outside, kA, kB, kC);
  EXPECT_GE(w.minCoeff(), 0.0);
  EXPECT_NEAR(w.sum(), 1.0, 1e-14);
  EXPECT_TRUE(w.isApprox(Eigen::Vector3d(0, 1, 0), 1e-14)) << w.transpose();
  // Inside, the same as unclamped.
  const Eigen::Vector3d q(0.25, 0.5, 0);
  EXPECT_TRUE(ClampedTriangleCoordinates(q, kA, kB, kC)
                  .isApprox(TriangleCoordinates(q, kA, kB, kC), 1e-14));
  // Degenerate: the centroid's weights.
  EXPECT_TRUE(ClampedTriangleCoordinates(q, kA, kA, kB)
                  .isApprox(Eigen::Vector3d::Constant(1.0 / 3), 1e-14));
}

}  // namespace
}  // namespace sdcb
