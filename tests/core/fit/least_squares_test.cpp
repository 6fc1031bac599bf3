// Tests core/least_squares.* against a dense QR solve of the same
// regularized problem, and the prior's definition.
#include "sdcb/core/fit/least_squares.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

namespace sdcb {
namespace {

DesignMatrix RandomSparse(int rows, int cols, int per_row, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> col(0, cols - 1);
  std::uniform_real_distribution<double> value(0.05, 1.0);
  std::vector<Eigen::Triplet<double>> t;
  for (int r = 0; r < rows; ++r) {
    for (int k = 0; k < per_row; ++k) t.emplace_back(r, col(rng), value(rng));
  }
  DesignMatrix a(rows, cols);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

TEST(LeastSquaresTest, MatchesDenseQrOfTheAugmentedSystem) {
  const int rows = 300, cols = 60;
  const DesignMatrix a = RandomSparse(rows, cols, 5, 3);
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  Eigen::MatrixX3d x(rows, 3), prior(cols, 3);
  for (int i = 0; i < rows; ++i) x.row(i) << g(rng), g(rng), g(rng);
  for (int i = 0; i < cols; ++i) prior.row(i) << g(rng), g(rng), g(rng);
  for (double reg : {1e-6, 1e-2, 1.0}) {
    LeastSquaresOptions options;
    options.regularization = reg;
    auto c = SolveRegularizedLeastSquares(a, x, prior, options);
    ASSERT_TRUE(c.ok()) << c.status().message();
    // Oracle: [A; sqrt(mu) I] C = [X; sqrt(mu) P] by dense Householder QR.
    const Eigen::MatrixXd dense = Eigen::MatrixXd(a);
    const double mu = reg * (dense.transpose() * dense).trace() / cols;
    Eigen::MatrixXd stacked(rows + cols, cols);
    stacked << dense, std::sqrt(mu) * Eigen::MatrixXd::Identity(cols, cols);
    Eigen::MatrixXd rhs(rows + cols, 3);
    rhs << x, std::sqrt(mu) * prior;
    const Eigen::MatrixXd expected = stacked.colPivHouseholderQr().solve(rhs);
    EXPECT_LT((*c - expected).cwiseAbs().maxCoeff(),
              1e-9 * (1 + expected.norm()))
        << "regularization " << reg;
  }
}

// The matrix the solve factors, which the fold repair reuses: the lower
// triangle of A^T A + mu I against the dense product.
TEST(LeastSquaresTest, RegularizedNormalMatrixIsTheDenseProductPlusMu) {
  const int rows = 200, cols = 40;
  const DesignMatrix a = RandomSparse(rows, cols, 4, 9);
  double mu = 0;
  const Eigen::SparseMatrix<double> lower =
      RegularizedNormalMatrixLower(a, 1e-3, &mu);
  const Eigen::MatrixXd dense = Eigen::MatrixXd(a);
  const Eigen::MatrixXd product = dense.transpose() * dense;
  EXPECT_NEAR(mu, 1e-3 * product.trace() / cols, 1e-15 * product.trace());
  const Eigen::MatrixXd expected =
      product + mu * Eigen::MatrixXd::Identity(cols, cols);
  const Eigen::MatrixXd got = Eigen::MatrixXd(lower);
  for (int i = 0; i < cols; ++i) {
    for (int j = 0; j < cols; ++j) {
      EXPECT_NEAR(got(i, j), i >= j ? expected(i, j) : 0.0, 1e-12)
          << i << ", " << j;
    }
  }
}

TEST(LeastSquaresTest, ColumnsWithoutSamplesStayAtTheirPrior) {
  // Column 3 has no samples: its control point is exactly the prior.
  DesignMatrix a(4, 4);
  std::vector<Eigen::Triplet<double>> t = {
      {0, 0, 1}, {1, 1, 1}, {2, 2, 1}, {3, 0, 0.5}};
  a.setFromTriplets(t.begin(), t.end());
  Eigen::MatrixX3d x = Eigen::MatrixX3d::Random(4, 3);
  Eigen::MatrixX3d prior = Eigen::MatrixX3d::Random(4, 3);
  auto c = SolveRegularizedLeastSquares(a, x, prior);
  ASSERT_TRUE(c.ok());
  EXPECT_LT((c->row(3) - prior.row(3)).norm(), 1e-12);
  EXPECT_LT((c->row(1) - x.row(1)).norm(), 1e-5);  // well-sampled: the data
}

TEST(LeastSquaresTest, GrevillePriorTakesTheSampleWhereTheColumnPeaks) {
  DesignMatrix a(3, 3);
  std::vector<Eigen::Triplet<double>> t = {
      {0, 0, 0.2}, {1, 0, 0.7}, {2, 0, 0.7}, {0, 1, 0.9}, {2, 1, 0.1}};
  a.setFromTriplets(t.begin(), t.end());
  Eigen::MatrixX3d x(3, 3);
  x << 1, 0, 0, 2, 0, 0, 3, 0, 0;
  Eigen::MatrixX3d fallback = Eigen::MatrixX3d::Constant(3, 3, 9);
  const Eigen::MatrixX3d p = GrevillePrior(a, x, fallback);
  EXPECT_EQ(p(0, 0), 2);  // rows 1 and 2 tie at 0.7: the lower row wins
  EXPECT_EQ(p(1, 0), 1);
  EXPECT_EQ(p(2, 0), 9);  // no samples: fallback
}

TEST(LeastSquaresTest, RefusesMismatchedSizes) {
  DesignMatrix a(3, 2);
  EXPECT_FALSE(SolveRegularizedLeastSquares(a, Eigen::MatrixX3d::Zero(2, 3),
                                            Eigen::MatrixX3d::Zero(2, 3))
                   .ok());
  EXPECT_FALSE(SolveRegularizedLeastSquares(a, Eigen::MatrixX3d::Zero(3, 3),
                                            Eigen::MatrixX3d::Zero(3, 3))
                   .ok());
}

}  // namespace
}  // namespace sdcb
