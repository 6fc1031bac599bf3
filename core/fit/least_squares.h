// Control points by regularized sparse least squares (paper Sec. 4.5):
//
//   min_C  |A C - X|^2 + mu |C - P|^2,
//
// A the #samples by #basis design matrix (core/spline/design_matrix.h), X the
// sample positions, P a prior for every control point. The prior term keeps
// basis functions with few or no samples well-posed without pulling them
// toward the origin: P_i is the position of the sample where basis i is
// largest (a Greville-like point), so the regularized solution stays on the
// surface. mu = regularization * trace(A^T A) / #basis: relative to the
// average diagonal, so it does not depend on the model's scale or size.
#ifndef SDCB_CORE_FIT_LEAST_SQUARES_H_
#define SDCB_CORE_FIT_LEAST_SQUARES_H_

#include <Eigen/Core>

#include "sdcb/core/common/status.h"
#include "sdcb/core/spline/design_matrix.h"

namespace sdcb {

struct LeastSquaresOptions {
  // Weight of the prior term relative to the mean diagonal of A^T A. The
  // default changes a well-sampled fit by far less than its residual.
  double regularization = 1e-6;
};

// Solves the problem above by the normal equations (A^T A + mu I) C =
// A^T X + mu P with a sparse Cholesky factorization (CHOLMOD supernodal LL^T;
// Eigen's simplicial LDL^T if that fails).
// `samples`: #A.rows() by 3; `prior`: #A.cols() by 3. Returns #A.cols() by
// 3. kInvalidArgument on size mismatch; kInternal if the factorization
// fails (not expected: the matrix is positive definite for mu > 0).
StatusOr<Eigen::MatrixX3d> SolveRegularizedLeastSquares(
    const DesignMatrix& design, const Eigen::MatrixX3d& samples,
    const Eigen::MatrixX3d& prior, const LeastSquaresOptions& options = {});

// The lower triangle of A^T A + mu I, the matrix the solve above factors
// (mu as there, returned in `mu` when not null). Requires regularization > 0.
Eigen::SparseMatrix<double> RegularizedNormalMatrixLower(
    const DesignMatrix& design, double regularization, double* mu = nullptr);

// Solves N X = rhs for a symmetric positive definite N given by its lower
// triangle (entries above the diagonal are ignored): CHOLMOD's supernodal
// LL^T, Eigen's simplicial LDL^T if that fails. kInvalidArgument on size
// mismatch; kInternal if both factorizations fail.
StatusOr<Eigen::MatrixX3d> SolveNormalEquations(
    const Eigen::SparseMatrix<double>& lower, const Eigen::MatrixX3d& rhs);

// The lower triangle of A^T A (the diagonal first in every column),
// computed in parallel; deterministic for any thread count.
Eigen::SparseMatrix<double> NormalMatrixLower(const DesignMatrix& design);

// The prior P of the header comment: for every column, the sample (row of
// `samples`) where that column's value is largest (lowest row on ties).
// Columns without any nonzero get `fallback` (one row per column; pass the
// surface point nearest the column's support, see core/fit/adaptive_fit.cpp).
Eigen::MatrixX3d GrevillePrior(const DesignMatrix& design,
                               const Eigen::MatrixX3d& samples,
                               const Eigen::MatrixX3d& fallback);

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_LEAST_SQUARES_H_
