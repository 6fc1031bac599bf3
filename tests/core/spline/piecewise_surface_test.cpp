#include "sdcb/core/spline/piecewise_surface.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "testing/random_spline.h"
#include "testing/spline_model_fixture.h"

namespace sdcb {
namespace {

using testing::RandomSpline;
using testing::SplineOnKnots;

TEST(PiecewiseSurfaceTest, AgreesWithTheReferenceEvaluator) {
  for (int degree : {2, 3, 4, -4}) {
    // -4: degree 4 with the raw basis of eq. 4 (F = N / |x|^k).
    SCOPED_TRACE(degree);
    const BasisForm form =
        degree < 0 ? BasisForm::kRaw : BasisForm::kNormalized;
    degree = std::abs(degree);
    const SphericalSpline spline = RandomSpline(degree, 60, 5 + degree, form);
    const PiecewiseSurface fast(spline);
    const Eigen::MatrixX3d points = testing::RandomUnitVectors(4000, 99);
    Eigen::MatrixX3d positions, normals;
    fast.EvaluateMany(points, &positions, &normals);
    const std::vector<SurfacePoint> exact =
        spline.EvaluateDifferentialMany(points, JetOrder::kGradient);
    double worst = 0.0, worst_normal = 0.0;
    for (Eigen::Index r = 0; r < points.rows(); ++r) {
      const double scale = std::max(1.0, exact[r].position.norm());
      worst = std::max(
          worst,
          (positions.row(r).transpose() - exact[r].position).norm() / scale);
      worst_normal = std::max(
          worst_normal, (normals.row(r).transpose() - exact[r].normal).norm());
    }
    EXPECT_LE(worst, 1e-12);
    EXPECT_LE(worst_normal, 1e-8);
    EXPECT_GT(fast.num_regions(), 0);
    // Evaluating again (all regions built) gives identical bits.
    Eigen::MatrixX3d again;
    fast.EvaluateMany(points, &again, nullptr);
    EXPECT_EQ(again, positions);
  }
}

// The root cells take their candidate segments and basis functions from
// their face's and their block's (4 x 4 root cells) caps: a segment dropped
// there would leave a cell without a line that crosses it, and at degree 0
// (the surface jumps across every segment) its region would then be wrong by
// O(1) near the line. Grids smaller than, equal to and not multiples of the
// block, many knots (short segments, small caps).
TEST(PiecewiseSurfaceTest, AgreesForEveryGridSize) {
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(3000, 5);
  for (int degree : {0, 2}) {
    const SphericalSpline spline = RandomSpline(degree, 150, 31 + degree);
    const std::vector<SurfacePoint> exact =
        spline.EvaluateDifferentialMany(points, JetOrder::kValue);
    for (int grid : {1, 2, 3, 4, 5, 7, 9, 13, 24}) {
      SCOPED_TRACE(::testing::Message()
                   << "degree " << degree << " grid " << grid);
      const PiecewiseSurface fast(spline, grid);
      ASSERT_EQ(fast.grid(), grid);
      Eigen::MatrixX3d positions;
      fast.EvaluateMany(points, &positions, nullptr);
      int wrong = 0;
      for (Eigen::Index r = 0; r < points.rows(); ++r) {
        const double scale = std::max(1.0, exact[r].position.norm());
        // !(error <= bound) so that NaN counts as wrong.
        if (!((positions.row(r).transpose() - exact[r].position).norm() /
                  scale <=
              1e-12)) {
          ++wrong;
        }
      }
      EXPECT_EQ(wrong, 0);
    }
  }
}

// Points where a wrong region or a wrong cell would show: exactly on knots
// and on knot segments' great circles (the exact, perturbed signs decide
// there), on cube-face edges and corners and on the grid's cell boundaries.
// At degree 0 the surface jumps across every knot segment and at degree 1 its
// normal does, so a region from the wrong side of a line differs from
// SphericalSpline's by O(1) there; degrees 2 and 4 check the same points
// where the pieces join smoothly.
TEST(PiecewiseSurfaceTest, AgreesOnKnotsSegmentsAndCellBoundaries) {
  // Random knots plus the six axes: the coordinate planes hold knot
  // segments, and points with a zero coordinate lie exactly on them.
  Eigen::MatrixX3d knots(46, 3);
  knots.topRows(40) = testing::RandomUnitVectors(40, 17);
  for (int a = 0; a < 3; ++a) {
    knots.row(40 + 2 * a) = Eigen::RowVector3d::Unit(a);
    knots.row(41 + 2 * a) = -Eigen::RowVector3d::Unit(a);
  }
  for (int degree : {0, 1, 2, 4}) {
    SCOPED_TRACE(degree);
    const SphericalSpline spline = SplineOnKnots(knots, degree, 23 + degree);
    const PiecewiseSurface fast(spline);
    const int g = fast.grid();
    std::vector<Eigen::Vector3d> points;
    for (Eigen::Index r = 0; r < knots.rows(); ++r) {
      points.push_back(knots.row(r).transpose());
      points.push_back(-knots.row(r).transpose());
    }
    for (int i = 0; i < 720; ++i) {
      const double angle = 2.0 * kPi * i / 720.0;
      const double c = std::cos(angle), s = std::sin(angle);
      points.emplace_back(c, s, 0.0);
      points.emplace_back(0.0, c, s);
      points.emplace_back(s, 0.0, c);
      // Cube-face edges (|x| = |y| and so on).
      points.push_back(Eigen::Vector3d(c, c, s).normalized());
      points.push_back(Eigen::Vector3d(s, -c, -c).normalized());
    }
    for (int corner = 0; corner < 8; ++corner) {
      points.push_back(Eigen::Vector3d(corner & 1 ? 1 : -1, corner & 2 ? 1 : -1,
                                       corner & 4 ? 1 : -1)
                           .normalized());
    }
    // Grid lines u = -1 + 2 i / G of every face, at several v.
    for (int i = 0; i <= g; ++i)
      for (int j = 0; j < 7; ++j) {
        const double u = -1.0 + 2.0 * i / g, v = -0.95 + 0.3 * j;
        for (int f = 0; f < 3; ++f) {
          Eigen::Vector3d p;
          p[f] = 1.0;
          p[(f + 1) % 3] = u;
          p[(f + 2) % 3] = v;
          points.push_back(p.normalized());
          points.push_back(-Eigen::Vector3d(p[0], p[2], p[1]).normalized());
        }
      }
    Eigen::MatrixX3d directions(points.size(), 3);
    for (size_t r = 0; r < points.size(); ++r) {
      directions.row(r) = points[r].transpose();
    }
    Eigen::MatrixX3d positions, normals;
    fast.EvaluateMany(directions, &positions, &normals);
    // Counted with !(error <= bound) so that NaN counts as wrong.
    int wrong = 0, wrong_normals = 0, not_as_batch = 0;
    for (size_t r = 0; r < points.size(); ++r) {
      const SurfacePoint exact =
          spline.EvaluateDifferential(points[r], JetOrder::kGradient);
      const double scale = std::max(1.0, exact.position.norm());
      if (!((positions.row(r).transpose() - exact.position).norm() / scale <=
            1e-12)) {
        ++wrong;
      }
      if (degree > 0 &&
          !((normals.row(r).transpose() - exact.normal).norm() <= 1e-8)) {
        ++wrong_normals;
      }
      // One point at a time gives the same bits as the batch.
      if (!(fast.Evaluate(points[r]) == positions.row(r).transpose())) {
        ++not_as_batch;
      }
    }
    EXPECT_EQ(wrong, 0) << "of " << points.size() << " points";
    EXPECT_EQ(not_as_batch, 0);
    EXPECT_EQ(wrong_normals, 0) << "of " << points.size() << " points";
  }
}

}  // namespace
}  // namespace sdcb
