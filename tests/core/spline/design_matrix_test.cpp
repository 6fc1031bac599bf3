#include "sdcb/core/spline/design_matrix.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/SparseCholesky>
#include <cmath>

#include "sdcb/core/spline/spherical_spline.h"
#include "testing/brute_force_configurations.h"
#include "testing/random_sphere_points.h"

namespace sdcb {
namespace {

// The degree-k basis on `knots`, configurations from the brute-force oracle.
DcbBasis OracleBasis(const Eigen::MatrixX3d& knots, int degree) {
  StatusOr<DcbBasis> basis =
      DcbBasis::Create(knots, testing::BruteForceConfigurations(knots, degree));
  EXPECT_TRUE(basis.ok()) << basis.status().message();
  return std::move(basis).value();
}

TEST(DesignMatrix, EntriesAreNormalizedBasisValuesOfEveryFunction) {
  const DcbBasis basis = OracleBasis(testing::RandomUnitVectors(70, 1), 3);
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(500, 2);
  const DesignMatrix a = BuildDesignMatrix(basis, points);
  ASSERT_EQ(a.rows(), 500);
  ASSERT_EQ(a.cols(), basis.size());
  // Oracle: all basis functions, without the support index.
  for (int r = 0; r < points.rows(); ++r) {
    const Eigen::Vector3d p = points.row(r);
    Eigen::VectorXd all(basis.size());
    for (int i = 0; i < basis.size(); ++i) all[i] = basis.Value(i, p);
    all /= all.sum();
    const Eigen::VectorXd row = Eigen::VectorXd(a.row(r).transpose());
    EXPECT_LT((row - all).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_NEAR(row.sum(), 1.0, 1e-14);
    EXPECT_EQ(a.row(r).nonZeros(), (all.array() != 0).count());
  }
}

TEST(DesignMatrix, TimesControlPointsIsTheSurfaceAndThreadIndependent) {
  DcbBasis basis = OracleBasis(testing::RandomUnitVectors(90, 3), 2);
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(4000, 4);
  DesignMatrix one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = BuildDesignMatrix(basis, points);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = BuildDesignMatrix(basis, points);
  }
  ASSERT_EQ(one.nonZeros(), two.nonZeros());
  for (Eigen::Index i = 0; i < one.nonZeros(); ++i) {
    ASSERT_EQ(one.valuePtr()[i], two.valuePtr()[i]);
    ASSERT_EQ(one.innerIndexPtr()[i], two.innerIndexPtr()[i]);
  }
  const Eigen::MatrixX3d control = testing::RandomUnitVectors(basis.size(), 5);
  StatusOr<SphericalSpline> spline =
      SphericalSpline::Create(std::move(basis), control);
  ASSERT_TRUE(spline.ok());
  const Eigen::MatrixX3d f = one * control;
  EXPECT_LT((f - spline->EvaluateMany(points)).cwiseAbs().maxCoeff(), 1e-13);
}

// Least-squares max error of fitting a smooth function with degree-2
// splines on n Fibonacci knots (quasi-uniform), sampled at 12 points per
// basis function.
double FitError(int n, bool normalized) {
  const DcbBasis basis = OracleBasis(testing::FibonacciPoints(n, 77), 2);
  auto f = [](const Eigen::MatrixX3d& x) {
    Eigen::VectorXd out(x.rows());
    for (int r = 0; r < x.rows(); ++r) {
      out[r] = std::exp(0.8 * x(r, 0)) * std::sin(1.5 * x(r, 1) + x(r, 2));
    }
    return out;
  };
  DesignMatrixOptions options;
  options.normalized = normalized;
  const Eigen::MatrixX3d samples =
      testing::RandomUnitVectors(12 * basis.size(), 78);
  const Eigen::SparseMatrix<double> a =
      BuildDesignMatrix(basis, samples, options);
  const Eigen::SparseMatrix<double> normal = a.transpose() * a;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
  EXPECT_EQ(solver.info(), Eigen::Success);
  const Eigen::VectorXd c = solver.solve(a.transpose() * f(samples));
  const Eigen::MatrixX3d test = testing::RandomUnitVectors(5000, 79);
  return (BuildDesignMatrix(basis, test, options) * c - f(test))
      .cwiseAbs()
      .maxCoeff();
}

// Halving the knot spacing (4x knots) should divide the max error by about
// 2^(k+1) = 8 for k = 2; loose bound 4 (orders are reported by
// bench/approximation_order_bench).
TEST(DesignMatrix, LeastSquaresErrorFallsWithTheKnotSpacing) {
  for (bool normalized : {true, false}) {
    const double coarse = FitError(40, normalized);
    const double fine = FitError(160, normalized);
    EXPECT_GT(coarse / fine, 4.0) << "normalized " << normalized;
    EXPECT_LT(fine, 5e-3);
  }
}

}  // namespace
}  // namespace sdcb

namespace sdcb {
namespace {

// Values reused from a previous knot set (the fitting rounds) are exactly
// the values a fresh evaluation gives.
TEST(DesignMatrix, ReusedColumnsAreBitIdenticalToAFreshBuild) {
  const Eigen::MatrixX3d all = testing::RandomUnitVectors(90, 31);
  const Eigen::MatrixX3d first = all.topRows(70);
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(4000, 32);
  const int degree = 3;
  auto configs_a = ComputeDelaunayConfigurations(first, degree);
  auto configs_b = ComputeDelaunayConfigurations(all, degree);
  ASSERT_TRUE(configs_a.ok() && configs_b.ok());
  auto basis_a = DcbBasis::Create(first, *configs_a);
  auto basis_b = DcbBasis::Create(all, *configs_b);
  ASSERT_TRUE(basis_a.ok() && basis_b.ok());
  const DesignMatrix raw_a = BuildRawDesignMatrix(*basis_a, points);
  // Column of the identical function in round a, by brute-force comparison.
  std::vector<int> previous(basis_b->size(), -1);
  int reused = 0;
  for (int i = 0; i < basis_b->size(); ++i) {
    for (int j = 0; j < basis_a->size(); ++j) {
      if (configs_b->sets[i].knots == configs_a->sets[j].knots &&
          configs_b->sets[i].boundaries == configs_a->sets[j].boundaries) {
        previous[i] = j;
        ++reused;
      }
    }
  }
  EXPECT_GT(reused, basis_b->size() / 10);  // some functions are reused
  const DesignMatrix with_reuse =
      BuildRawDesignMatrix(*basis_b, points, &raw_a, &previous);
  const DesignMatrix fresh = BuildDesignMatrix(*basis_b, points, {false});
  ASSERT_EQ(with_reuse.nonZeros(), fresh.nonZeros());
  EXPECT_TRUE(
      (Eigen::MatrixXd(with_reuse).array() == Eigen::MatrixXd(fresh).array())
          .all());
  const DesignMatrix normalized = BuildDesignMatrix(*basis_b, points);
  EXPECT_TRUE((Eigen::MatrixXd(NormalizeRows(with_reuse)).array() ==
               Eigen::MatrixXd(normalized).array())
                  .all());
}

TEST(DesignMatrix, RowsStackedFromBatchesAreBitIdenticalToOneBuild) {
  // The fold repair builds its chart rows as samples join and stacks them:
  // a row depends only on its point, so the stack is the one-batch build.
  const DcbBasis basis = OracleBasis(testing::RandomUnitVectors(80, 41), 4);
  const Eigen::MatrixX3d points = testing::RandomUnitVectors(900, 42);
  const ChartGradientRows whole =
      BuildChartGradientRows(basis, points, BasisForm::kNormalized);
  const ChartGradientRows head = BuildChartGradientRows(
      basis, points.topRows(350), BasisForm::kNormalized);
  const ChartGradientRows tail = BuildChartGradientRows(
      basis, points.bottomRows(550), BasisForm::kNormalized);
  const Eigen::VectorXd half = Eigen::VectorXd::Constant(550, 0.5);
  const DesignMatrix u =
      StackScaledRows({{&head.u, nullptr}, {&tail.u, nullptr}});
  const DesignMatrix v_scaled =
      StackScaledRows({{&head.v, nullptr}, {&tail.v, &half}});
  ASSERT_EQ(u.rows(), 900);
  ASSERT_EQ(u.nonZeros(), whole.u.nonZeros());
  for (Eigen::Index i = 0; i <= u.rows(); ++i) {
    ASSERT_EQ(u.outerIndexPtr()[i], whole.u.outerIndexPtr()[i]);
  }
  for (Eigen::Index k = 0; k < u.nonZeros(); ++k) {
    ASSERT_EQ(u.innerIndexPtr()[k], whole.u.innerIndexPtr()[k]);
    ASSERT_EQ(u.valuePtr()[k], whole.u.valuePtr()[k]);
  }
  // The scale multiplies each row of its part only.
  const Eigen::MatrixXd dense_v(whole.v), dense_scaled(v_scaled);
  EXPECT_TRUE(
      (dense_scaled.topRows(350).array() == dense_v.topRows(350).array())
          .all());
  EXPECT_TRUE((dense_scaled.bottomRows(550).array() ==
               0.5 * dense_v.bottomRows(550).array())
                  .all());
}

}  // namespace
}  // namespace sdcb
