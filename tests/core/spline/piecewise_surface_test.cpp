#include "sdcb/core/spline/piecewise_surface.h"

#include <gtest/gtest.h>

#include <random>

#include "sdcb/core/spline/delaunay_configurations.h"
#include "testing/spline_model_fixture.h"

namespace sdcb {
namespace {

// A spline on random knots with random control points (the fit is not the
// point: any valid spline, folds included).
SphericalSpline RandomSpline(int degree, int knots, unsigned seed,
                             BasisForm form = BasisForm::kNormalized) {
  const Eigen::MatrixX3d k = testing::RandomUnitVectors(knots, seed);
  StatusOr<DelaunayConfigurations> c = ComputeDelaunayConfigurations(k, degree);
  EXPECT_TRUE(c.ok());
  StatusOr<DcbBasis> basis = DcbBasis::Create(k, *c);
  EXPECT_TRUE(basis.ok()) << basis.status().message();
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  Eigen::MatrixX3d cp(basis->size(), 3);
  for (int i = 0; i < basis->size(); ++i) {
    // Near a sphere of radius 1, perturbed.
    const Eigen::Vector3d dir = k.row(basis->configuration_set(i).knots[0]);
    cp.row(i) =
        (dir + 0.2 * Eigen::Vector3d(g(rng), g(rng), g(rng))).transpose();
  }
  return std::move(SphericalSpline::Create(std::move(*basis), cp, form))
      .value();
}

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

}  // namespace
}  // namespace sdcb
