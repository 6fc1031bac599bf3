#include "core/least_squares.h"

#include <Eigen/SparseCholesky>
#include <limits>
#include <vector>

namespace sdcb {

StatusOr<Eigen::MatrixX3d> SolveRegularizedLeastSquares(
    const DesignMatrix& design, const Eigen::MatrixX3d& samples,
    const Eigen::MatrixX3d& prior, const LeastSquaresOptions& options) {
  const Eigen::Index m = design.cols();
  if (samples.rows() != design.rows() || prior.rows() != m) {
    return InvalidArgumentError(
        "least squares: sizes of the design matrix, samples and prior differ");
  }
  if (!(options.regularization > 0)) {
    return InvalidArgumentError("least squares: regularization must be > 0");
  }
  const Eigen::SparseMatrix<double> a = design;  // column-major copy
  Eigen::SparseMatrix<double> normal = a.transpose() * a;
  const double mean_diagonal =
      normal.diagonal().sum() / std::max<Eigen::Index>(m, 1);
  const double mu =
      options.regularization * (mean_diagonal > 0 ? mean_diagonal : 1.0);
  for (Eigen::Index i = 0; i < m; ++i) normal.coeffRef(i, i) += mu;
  const Eigen::MatrixX3d rhs = a.transpose() * samples + mu * prior;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
  if (solver.info() != Eigen::Success) {
    return InternalError("least squares: the sparse factorization failed");
  }
  Eigen::MatrixX3d c = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !c.allFinite()) {
    return InternalError("least squares: the sparse solve failed");
  }
  return c;
}

Eigen::MatrixX3d GrevillePrior(const DesignMatrix& design,
                               const Eigen::MatrixX3d& samples,
                               const Eigen::MatrixX3d& fallback) {
  const Eigen::Index m = design.cols();
  std::vector<double> best(m, -std::numeric_limits<double>::infinity());
  std::vector<Eigen::Index> best_row(m, -1);
  for (Eigen::Index r = 0; r < design.outerSize(); ++r) {
    for (DesignMatrix::InnerIterator it(design, r); it; ++it) {
      if (it.value() > best[it.col()]) {  // strict: lowest row wins ties
        best[it.col()] = it.value();
        best_row[it.col()] = r;
      }
    }
  }
  Eigen::MatrixX3d prior(m, 3);
  for (Eigen::Index i = 0; i < m; ++i) {
    prior.row(i) =
        best_row[i] >= 0 ? samples.row(best_row[i]) : fallback.row(i);
  }
  return prior;
}

}  // namespace sdcb
