// Creases made by knots: a spherical DCB-spline is C^(k+1-m) across a great
// circle that carries m knots of every simplex spline whose support crosses
// it. The cube, parameterized radially, has its 12 edges on 6 great circles
// (each through an edge and its opposite). With every corner a cluster of
// four knots (the corner and one knot a hair from it along each of its
// three edges), each of those great circles carries eight knots, and the
// spline reproduces the cube: flat faces, sharp edges and corners. The
// oracle is the closed-form cube (tests/testing/cube_creases.h).
#include "testing/cube_creases.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "sdcb/core/spline/piecewise_surface.h"

namespace sdcb {
namespace {

TEST(CubeCreases, ClusteredCornerKnotsReproduceTheCube) {
  testing::CubeKnotLayout layout;  // 8 corners + 24 knots 1e-6 from them
  const Eigen::MatrixX3d knots = testing::CubeKnots(layout);
  ASSERT_EQ(knots.rows(), 32);
  // Control points of the 32 knots' configurations, degrees 2, 3, 4.
  const int control_points[] = {153, 171, 212};
  for (int degree = 2; degree <= 4; ++degree) {
    auto spline = testing::FitCubeSpline(knots, degree);
    ASSERT_TRUE(spline.ok()) << spline.status().message();
    EXPECT_EQ(spline->basis().size(), control_points[degree - 2]);
    const testing::CubeMeasures m = testing::MeasureCube(*spline);
    std::printf("degree %d: max %.3g %%, rms %.3g %%, normal %.3g deg\n",
                degree, m.max_percent, m.rms_percent, m.max_normal_degrees);
    // Flat faces and sharp edges: the distance off the fitted grid and the
    // normals on both sides of every edge, 1 % of the diagonal from it.
    EXPECT_LT(m.max_percent, 1e-3) << degree;
    EXPECT_LT(m.max_normal_degrees, 0.01) << degree;
  }
}

// The fast evaluator's pieces beside a crease are sums of terms up to 1e16
// (the thin triangles between a corner's cluster and the next corner) that
// cancel: those cells must fall back to the spline, whose value the pieces
// must equal to rounding (without the fallback they are off by 2e7) at
// points from 1e-7 to 1e-3 radians off every edge.
TEST(CubeCreases, PiecewiseSurfaceAgreesBesideTheCreases) {
  auto spline = testing::FitCubeSpline(testing::CubeKnots({}), 4);
  ASSERT_TRUE(spline.ok()) << spline.status().message();
  const PiecewiseSurface fast(*spline);
  const Eigen::MatrixX3d& knots = spline->knots();
  Eigen::MatrixX3d directions(12 * 101 * 18, 3);
  Eigen::Index row = 0;
  for (int i = 0; i < 8; ++i) {
    for (int j = i + 1; j < 8; ++j) {
      const Eigen::Vector3d a = knots.row(i).normalized();
      const Eigen::Vector3d b = knots.row(j).normalized();
      if (std::abs(a.dot(b) - 1.0 / 3.0) > 1e-9) continue;  // not an edge
      const Eigen::Vector3d side = a.cross(b).normalized();
      for (int s = 0; s <= 100; ++s) {
        const Eigen::Vector3d on = (a * (100 - s) + b * s).normalized();
        for (int e = 0; e < 9; ++e) {
          for (int sign = -1; sign <= 1; sign += 2) {
            const double offset = sign * std::pow(10.0, -7.0 + 0.5 * e);
            directions.row(row++) = (on + offset * side).normalized();
          }
        }
      }
    }
  }
  ASSERT_EQ(row, directions.rows());
  Eigen::MatrixX3d positions;
  fast.EvaluateMany(directions, &positions, nullptr);
  double worst = 0.0;
  for (Eigen::Index r = 0; r < row; ++r) {
    const Eigen::Vector3d reference =
        spline->Evaluate(directions.row(r).transpose());
    worst = std::max(worst, (positions.row(r).transpose() - reference).norm());
  }
  std::printf("pieces against the spline beside the edges: %.3g\n", worst);
  EXPECT_LT(worst, 1e-8);
}

TEST(CubeCreases, KnotsOffTheEdgesRoundThem) {
  // The corners and the edges' midpoints: no great circle carries enough
  // knots of the configurations that cross it, so the spline is C2 across
  // every edge and rounds it.
  testing::CubeKnotLayout layout;
  layout.edge_segments = 2;
  layout.corner_knots = 0;
  auto spline = testing::FitCubeSpline(testing::CubeKnots(layout), 3);
  ASSERT_TRUE(spline.ok()) << spline.status().message();
  const testing::CubeMeasures m = testing::MeasureCube(*spline);
  EXPECT_GT(m.max_percent, 1.0);
  EXPECT_GT(m.middle_normal_degrees, 10.0);
  // A degree-5 spline needs six knots of a crossing configuration on the
  // circle for C0: the clusters that crease the cubic round the quintic.
  testing::CubeKnotLayout clusters;
  auto quintic = testing::FitCubeSpline(testing::CubeKnots(clusters), 5);
  ASSERT_TRUE(quintic.ok()) << quintic.status().message();
  EXPECT_GT(testing::MeasureCube(*quintic).max_normal_degrees, 10.0);
}

}  // namespace
}  // namespace sdcb
