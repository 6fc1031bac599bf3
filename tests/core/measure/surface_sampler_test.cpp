#include "sdcb/core/measure/surface_sampler.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <memory>
#include <vector>

#include "sdcb/core/spline/piecewise_surface.h"
#include "sdcb/core/tessellate/optimal_triangle_count.h"
#include "testing/analytic_surfaces.h"
#include "testing/random_spline.h"

namespace sdcb {
namespace {

TEST(SurfaceSamplerTest, PiecewiseCurvatureAndShapeMatchTheSpline) {
  const SphericalSpline spline =
      testing::RandomSpline(4, 60, 31, BasisForm::kNormalized, 0.1);
  const PiecewiseSurface pieces(spline);
  const PiecewiseSplineSampler fast(spline, pieces);
  const SplineSampler exact(spline);
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(2000, 32);
  Eigen::VectorXd k_fast, h_fast, k_exact, h_exact;
  ASSERT_TRUE(fast.SampleCurvature(points, &k_fast, &h_fast));
  ASSERT_TRUE(exact.SampleCurvature(points, &k_exact, &h_exact));
  std::vector<SurfaceShape> s_fast, s_exact;
  ASSERT_TRUE(fast.SampleShape(points, &s_fast));
  ASSERT_TRUE(exact.SampleShape(points, &s_exact));
  ASSERT_EQ(s_fast.size(), static_cast<size_t>(points.rows()));
  for (Eigen::Index r = 0; r < points.rows(); ++r) {
    const double k = std::max(1.0, std::abs(k_exact[r]));
    const double h = std::max(1.0, std::abs(h_exact[r]));
    EXPECT_NEAR(k_fast[r], k_exact[r], 1e-8 * k);
    EXPECT_NEAR(h_fast[r], h_exact[r], 1e-8 * h);
    // The reference's shape is its curvature's.
    EXPECT_EQ(s_exact[r].gaussian_curvature, k_exact[r]);
    EXPECT_EQ(s_fast[r].gaussian_curvature, k_fast[r]);
    EXPECT_LE((s_fast[r].second_form - s_exact[r].second_form).norm(),
              1e-9 * s_exact[r].second_form.norm());
  }
}

TEST(SurfaceSamplerTest, CurvatureQuadratureWithEitherSampler) {
  // IntegrateCurvatureOverSurface, as export runs it, with the fast sampler
  // and with the reference: the same integrals to rounding.
  const SphericalSpline spline =
      testing::RandomSpline(4, 60, 33, BasisForm::kNormalized, 0.1);
  const PiecewiseSurface pieces(spline);
  const StatusOr<CurvatureIntegrals> fast =
      IntegrateCurvatureOverSurface(PiecewiseSplineSampler(spline, pieces), 4);
  const StatusOr<CurvatureIntegrals> exact =
      IntegrateCurvatureOverSurface(SplineSampler(spline), 4);
  ASSERT_TRUE(fast.ok());
  ASSERT_TRUE(exact.ok());
  EXPECT_NEAR(fast->convex, exact->convex, 1e-10 * exact->convex);
  EXPECT_NEAR(fast->saddle, exact->saddle, 1e-10 * exact->saddle);
  EXPECT_NEAR(fast->area, exact->area, 1e-12 * exact->area);
  EXPECT_GT(exact->saddle, 0.0);  // this spline folds: both signs of K
}

TEST(SurfaceSamplerTest, OnePointMethodsMatchTheBatches) {
  // Each spline sampler (through the basis and through the polynomials,
  // as MakeSplineSampler builds them): S, the normal and the derivatives at
  // one direction are the batch's row, to rounding.
  const SphericalSpline spline =
      testing::RandomSpline(3, 40, 35, BasisForm::kNormalized, 0.1);
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(200, 36);
  for (const bool polynomials : {false, true}) {
    const std::unique_ptr<SurfaceSampler> sampler =
        MakeSplineSampler(spline, polynomials);
    Eigen::MatrixX3d positions, normals;
    sampler->Sample(points, &positions, &normals);
    std::vector<SurfaceShape> shapes;
    ASSERT_TRUE(sampler->SampleShape(points, &shapes));
    for (Eigen::Index r = 0; r < points.rows(); ++r) {
      const Eigen::Vector3d p = points.row(r).transpose();
      const double scale = positions.row(r).norm();
      EXPECT_LE((sampler->Evaluate(p) - positions.row(r).transpose()).norm(),
                1e-13 * scale);
      EXPECT_LE(
          (sampler->EvaluateNormal(p) - normals.row(r).transpose()).norm(),
          1e-9);
      const SurfacePoint jet = sampler->EvaluateJet(p);
      EXPECT_LE((jet.position - positions.row(r).transpose()).norm(),
                1e-13 * scale);
      EXPECT_LE((jet.du - shapes[r].du).norm(), 1e-9 * shapes[r].du.norm());
      EXPECT_LE((jet.dv - shapes[r].dv).norm(), 1e-9 * shapes[r].dv.norm());
      EXPECT_NEAR(jet.frame_u.cross(jet.frame_v).dot(p), 1.0, 1e-12);
    }
  }
}

TEST(SurfaceSamplerTest, DefaultOnePointMethodsGoThroughTheBatch) {
  // A sampler with Sample only: Evaluate and EvaluateNormal are its rows;
  // EvaluateJet has the point and no derivatives (no SampleShape).
  const testing::EllipsoidSampler e(Eigen::Vector3d(1.0, 2.0, 3.0));
  const Eigen::Vector3d p = Eigen::Vector3d(1, -2, 0.5).normalized();
  EXPECT_TRUE(e.Evaluate(p).isApprox(Eigen::Vector3d(1, 2, 3).cwiseProduct(p)));
  EXPECT_TRUE(e.EvaluateNormal(p).isApprox(
      p.cwiseQuotient(Eigen::Vector3d(1, 2, 3)).normalized()));
  const SurfacePoint jet = e.EvaluateJet(p);
  EXPECT_TRUE(jet.position.isApprox(e.Evaluate(p)));
  EXPECT_TRUE(jet.du.isZero(0.0));
  EXPECT_TRUE(jet.dv.isZero(0.0));
}

}  // namespace
}  // namespace sdcb
