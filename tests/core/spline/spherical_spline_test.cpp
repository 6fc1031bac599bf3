#include "sdcb/core/spline/spherical_spline.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "testing/brute_force_configurations.h"
#include "testing/random_sphere_points.h"

namespace sdcb {
namespace {

// A degree-k spline on n random knots whose control points are a smooth
// deformation of the knot-set centroids (a bumpy closed surface).
SphericalSpline MakeSurface(int n, int degree, unsigned seed) {
  const Eigen::MatrixX3d knots = testing::RandomUnitVectors(n, seed);
  StatusOr<DcbBasis> basis =
      DcbBasis::Create(knots, testing::BruteForceConfigurations(knots, degree));
  EXPECT_TRUE(basis.ok());
  Eigen::MatrixX3d control(basis->size(), 3);
  for (int i = 0; i < basis->size(); ++i) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int q : basis->configuration_set(i).knots)
      c += knots.row(q).transpose();
    c.normalize();
    const double r = 1.0 + 0.2 * std::sin(3 * c.x()) * std::cos(2 * c.y());
    control.row(i) =
        (r * Eigen::Vector3d(1.0, 0.8, 1.3).cwiseProduct(c)).transpose();
  }
  StatusOr<SphericalSpline> spline =
      SphericalSpline::Create(std::move(basis).value(), control);
  EXPECT_TRUE(spline.ok());
  return std::move(spline).value();
}

TEST(SphericalSpline, ConstantControlPointsGiveAConstantSurface) {
  const Eigen::MatrixX3d knots = testing::RandomUnitVectors(50, 3);
  StatusOr<DcbBasis> basis =
      DcbBasis::Create(knots, testing::BruteForceConfigurations(knots, 3));
  ASSERT_TRUE(basis.ok());
  Eigen::MatrixX3d control(basis->size(), 3);
  control.rowwise() = Eigen::RowVector3d(1.5, -2.0, 0.25);
  StatusOr<SphericalSpline> spline =
      SphericalSpline::Create(std::move(basis).value(), control);
  ASSERT_TRUE(spline.ok());
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(200, 4);
  for (int r = 0; r < points.rows(); ++r) {
    const SurfacePoint s = spline->EvaluateDifferential(
        points.row(r).transpose(), JetOrder::kGradient);
    EXPECT_LT((s.position - Eigen::Vector3d(1.5, -2.0, 0.25)).norm(), 1e-13);
    EXPECT_LT(s.du.norm() + s.dv.norm(), 1e-11);
  }
}

// phi(u, v) = F(normalize(p + u e_u + v e_v)) by central differences: first
// derivatives with step h1, second with h2 (larger: rounding / h^2).
struct ChartDifferences {
  Eigen::Vector3d du, dv, duu, duv, dvv;
};
ChartDifferences Differences(const SphericalSpline& s, const SurfacePoint& at,
                             const Eigen::Vector3d& p, double h1, double h2) {
  auto f = [&](double u, double v) {
    return s.Evaluate((p + u * at.frame_u + v * at.frame_v).normalized());
  };
  ChartDifferences d;
  d.du = (f(h1, 0) - f(-h1, 0)) / (2 * h1);
  d.dv = (f(0, h1) - f(0, -h1)) / (2 * h1);
  const double h = h2;
  d.duu = (f(h, 0) - 2 * f(0, 0) + f(-h, 0)) / (h * h);
  d.dvv = (f(0, h) - 2 * f(0, 0) + f(0, -h)) / (h * h);
  d.duv = (f(h, h) - f(h, -h) - f(-h, h) + f(-h, -h)) / (4 * h * h);
  return d;
}

TEST(SphericalSpline, DerivativesNormalAndCurvaturesMatchFiniteDifferences) {
  for (int degree = 2; degree <= 4; ++degree) {
    const SphericalSpline s = MakeSurface(60, degree, 10 + degree);
    const Eigen::MatrixX3d points = testing::RandomUnitVectors(40, 20 + degree);
    for (int r = 0; r < points.rows(); ++r) {
      const Eigen::Vector3d p = points.row(r);
      const SurfacePoint a = s.EvaluateDifferential(p);
      EXPECT_LT((a.position - s.Evaluate(p)).norm(), 1e-13);
      const ChartDifferences d = Differences(s, a, p, 1e-6, 1e-4);
      const double scale = d.du.norm() + d.dv.norm();
      EXPECT_LT((a.du - d.du).norm(), 1e-6 * scale) << "degree " << degree;
      EXPECT_LT((a.dv - d.dv).norm(), 1e-6 * scale);
      const Eigen::Vector3d n = d.du.cross(d.dv).normalized();
      EXPECT_LT((a.normal - n).norm(), 1e-6);
      EXPECT_GT(a.normal.dot(a.position), 0.0);  // Outward on this surface.
      // Curvatures from the differenced fundamental forms.
      const double e = d.du.dot(d.du), f = d.du.dot(d.dv), g = d.dv.dot(d.dv);
      const double l = d.duu.dot(n), m = d.duv.dot(n), nn = d.dvv.dot(n);
      const double k = (l * nn - m * m) / (e * g - f * f);
      const double h = -(e * nn - 2 * f * m + g * l) / (2 * (e * g - f * f));
      // Second differences (h = 1e-4) carry ~1e-8 / 1e-8 rounding: loose.
      EXPECT_NEAR(a.gaussian_curvature, k, 1e-3 * (std::abs(k) + 1));
      EXPECT_NEAR(a.mean_curvature, h, 1e-3 * (std::abs(h) + 1));
    }
  }
}

// Differences of the tangent derivative and of the mean curvature between
// the two points at distance eps on either side of a knot segment's midpoint.
struct Jumps {
  double du, mean_curvature;
};
Jumps AcrossKnotLine(const SphericalSpline& s, const Eigen::Vector3d& ti,
                     const Eigen::Vector3d& tj, double eps) {
  const Eigen::Vector3d q = (ti + tj).normalized();
  const Eigen::Vector3d n = ti.cross(tj).normalized();
  const SurfacePoint a = s.EvaluateDifferential((q + eps * n).normalized());
  const SurfacePoint b = s.EvaluateDifferential((q - eps * n).normalized());
  // Same frame on both sides up to O(eps): compare frame-free quantities.
  return {std::abs(a.du.cross(a.dv).norm() - b.du.cross(b.dv).norm()),
          std::abs(a.mean_curvature - b.mean_curvature)};
}

// F is C^(k-1): across a knot line first derivatives are continuous for
// k >= 2 (differences shrink like eps), curvature (second derivatives)
// jumps for k = 2 and is continuous for k = 3.
TEST(SphericalSpline, SmoothnessOfTheSurfaceAcrossAKnotLine) {
  for (int degree : {2, 3}) {
    const SphericalSpline s = MakeSurface(60, degree, 60 + degree);
    const std::vector<int>& set = s.basis().configuration_set(0).knots;
    const Eigen::Vector3d ti = s.knots().row(set[0]),
                          tj = s.knots().row(set[1]);
    const Jumps wide = AcrossKnotLine(s, ti, tj, 1e-5);
    const Jumps narrow = AcrossKnotLine(s, ti, tj, 1e-7);
    EXPECT_LT(narrow.du, 0.05 * wide.du) << "degree " << degree;
    if (degree == 2) {
      EXPECT_GT(narrow.mean_curvature, 0.5 * wide.mean_curvature);
      EXPECT_GT(narrow.mean_curvature, 1e-6);
    } else {
      EXPECT_LT(narrow.mean_curvature, 0.05 * wide.mean_curvature);
    }
  }
}

TEST(SphericalSpline, CurvaturesScaleWithTheSurface) {
  // Scaling every control point by R scales F by R (partition of unity), so
  // H scales by 1/R and K by 1/R^2.
  const SphericalSpline s = MakeSurface(50, 2, 30);
  StatusOr<SphericalSpline> big = SphericalSpline::Create(
      s.basis(), Eigen::MatrixX3d(3.0 * s.control_points()));
  ASSERT_TRUE(big.ok());
  const Eigen::Vector3d p = Eigen::Vector3d(0.2, 0.9, -0.3).normalized();
  const SurfacePoint a = s.EvaluateDifferential(p),
                     b = big->EvaluateDifferential(p);
  EXPECT_NEAR(b.mean_curvature, a.mean_curvature / 3, 1e-10);
  EXPECT_NEAR(b.gaussian_curvature, a.gaussian_curvature / 9, 1e-10);
}

TEST(SphericalSpline, BatchEqualsSinglePointsForAnyThreadCount) {
  const SphericalSpline s = MakeSurface(80, 3, 40);
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(3000, 41);
  Eigen::MatrixX3d one, two;
  std::vector<SurfacePoint> d_one, d_two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = s.EvaluateMany(points);
    d_one = s.EvaluateDifferentialMany(points);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = s.EvaluateMany(points);
    d_two = s.EvaluateDifferentialMany(points);
  }
  EXPECT_TRUE((one.array() == two.array()).all());
  for (int r = 0; r < points.rows(); ++r) {
    EXPECT_TRUE((one.row(r).transpose().array() ==
                 s.Evaluate(points.row(r).transpose()).array())
                    .all());
    EXPECT_EQ(d_one[r].mean_curvature, d_two[r].mean_curvature);
    EXPECT_TRUE((d_one[r].normal.array() == d_two[r].normal.array()).all());
  }
}

TEST(SphericalSpline, RejectsWrongControlPointCount) {
  const SphericalSpline s = MakeSurface(20, 1, 50);
  EXPECT_EQ(SphericalSpline::Create(s.basis(), Eigen::MatrixX3d(3, 3))
                .status()
                .code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace sdcb
