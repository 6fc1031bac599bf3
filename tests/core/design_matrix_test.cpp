#include "core/design_matrix.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "core/brute_force_configurations.h"
#include "core/random_sphere_points.h"
#include "core/spherical_spline.h"

namespace sdcb {
namespace {

TEST(DesignMatrix, EntriesAreNormalizedBasisValuesOfEveryFunction) {
  const Eigen::MatrixX3d knots = testing::RandomUnitVectors(70, 1);
  StatusOr<DcbBasis> basis =
      DcbBasis::Create(knots, testing::BruteForceConfigurations(knots, 3));
  ASSERT_TRUE(basis.ok());
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(500, 2);
  const DesignMatrix a = BuildDesignMatrix(*basis, points);
  ASSERT_EQ(a.rows(), 500);
  ASSERT_EQ(a.cols(), basis->size());
  // Oracle: all basis functions, without the support index.
  for (int r = 0; r < points.rows(); ++r) {
    const Eigen::Vector3d p = points.row(r);
    Eigen::VectorXd all(basis->size());
    for (int i = 0; i < basis->size(); ++i) all[i] = basis->Value(i, p);
    all /= all.sum();
    const Eigen::VectorXd row = Eigen::VectorXd(a.row(r).transpose());
    EXPECT_LT((row - all).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_NEAR(row.sum(), 1.0, 1e-14);
    EXPECT_EQ(a.row(r).nonZeros(), (all.array() != 0).count());
  }
}

TEST(DesignMatrix, TimesControlPointsIsTheSurfaceAndThreadIndependent) {
  const Eigen::MatrixX3d knots = testing::RandomUnitVectors(90, 3);
  StatusOr<DcbBasis> basis =
      DcbBasis::Create(knots, testing::BruteForceConfigurations(knots, 2));
  ASSERT_TRUE(basis.ok());
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(4000, 4);
  DesignMatrix one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = BuildDesignMatrix(*basis, points);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = BuildDesignMatrix(*basis, points);
  }
  ASSERT_EQ(one.nonZeros(), two.nonZeros());
  for (Eigen::Index i = 0; i < one.nonZeros(); ++i) {
    ASSERT_EQ(one.valuePtr()[i], two.valuePtr()[i]);
    ASSERT_EQ(one.innerIndexPtr()[i], two.innerIndexPtr()[i]);
  }
  const Eigen::MatrixX3d control = testing::RandomUnitVectors(basis->size(), 5);
  StatusOr<SphericalSpline> spline =
      SphericalSpline::Create(std::move(basis).value(), control);
  ASSERT_TRUE(spline.ok());
  const Eigen::MatrixX3d f = one * control;
  EXPECT_LT((f - spline->EvaluateMany(points)).cwiseAbs().maxCoeff(), 1e-13);
}

}  // namespace
}  // namespace sdcb
