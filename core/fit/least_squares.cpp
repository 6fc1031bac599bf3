#include "sdcb/core/fit/least_squares.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

#include "sdcb/core/common/blas_lock.h"

namespace sdcb {

namespace {

// `design` with its rows in the order of their first column (counting sort,
// ties by row): the rows that meet one column then lie close together in
// memory, which the column-by-column product below reads them by.
DesignMatrix RowsByFirstColumn(const DesignMatrix& design) {
  const Eigen::Index n = design.rows();
  const int m = static_cast<int>(design.cols());
  std::vector<Eigen::Index> start(m + 2, 0);
  auto first = [&](Eigen::Index r) {
    const auto b = design.outerIndexPtr()[r], e = design.outerIndexPtr()[r + 1];
    return b < e ? design.innerIndexPtr()[b] : m;
  };
  for (Eigen::Index r = 0; r < n; ++r) ++start[first(r) + 1];
  for (int c = 0; c <= m; ++c) start[c + 1] += start[c];
  std::vector<Eigen::Index> order(n);
  for (Eigen::Index r = 0; r < n; ++r) order[start[first(r)]++] = r;
  DesignMatrix sorted(n, design.cols());
  sorted.resizeNonZeros(design.nonZeros());
  Eigen::Index at = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index r = order[k];
    sorted.outerIndexPtr()[k] = static_cast<int>(at);
    for (auto i = design.outerIndexPtr()[r]; i < design.outerIndexPtr()[r + 1];
         ++i, ++at) {
      sorted.innerIndexPtr()[at] = design.innerIndexPtr()[i];
      sorted.valuePtr()[at] = design.valuePtr()[i];
    }
  }
  sorted.outerIndexPtr()[n] = static_cast<int>(at);
  return sorted;
}

}  // namespace

Eigen::SparseMatrix<double> NormalMatrixLower(const DesignMatrix& unsorted) {
  const DesignMatrix design = RowsByFirstColumn(unsorted);
  const int m = static_cast<int>(design.cols());
  // Column-major copy: the rows where each column is nonzero.
  const Eigen::SparseMatrix<double> by_column = design;
  // Gustavson's algorithm, one column of the lower triangle at a time:
  // N(j, i) = sum over rows r of A(r, i) A(r, j), j >= i, accumulated in a
  // dense scratch row. Each column is computed alone, in a fixed order, so
  // the values do not depend on the thread count.
  std::vector<std::vector<std::pair<int, double>>> columns(m);
  tbb::parallel_for(
      tbb::blocked_range<int>(0, m, 64),
      [&](const tbb::blocked_range<int>& range) {
        std::vector<double> accumulator(m, 0.0);
        std::vector<char> seen(m, 0);
        std::vector<int> touched;
        for (int i = range.begin(); i < range.end(); ++i) {
          touched.clear();
          for (Eigen::SparseMatrix<double>::InnerIterator c(by_column, i); c;
               ++c) {
            const double a_ri = c.value();
            for (DesignMatrix::InnerIterator r(design, c.row()); r; ++r) {
              const int j = static_cast<int>(r.col());
              if (j < i) continue;
              if (!seen[j]) {
                seen[j] = 1;
                touched.push_back(j);
              }
              accumulator[j] += a_ri * r.value();
            }
          }
          if (!seen[i]) touched.push_back(i);  // the diagonal, even if empty
          std::sort(touched.begin(), touched.end());
          auto& column = columns[i];
          column.reserve(touched.size());
          for (int j : touched) {
            column.emplace_back(j, accumulator[j]);
            accumulator[j] = 0.0;
            seen[j] = 0;
          }
        }
      });
  Eigen::SparseMatrix<double> normal(m, m);
  Eigen::Index nonzeros = 0;
  for (const auto& column : columns) nonzeros += column.size();
  normal.resizeNonZeros(nonzeros);
  Eigen::Index at = 0;
  for (int i = 0; i < m; ++i) {
    normal.outerIndexPtr()[i] = static_cast<int>(at);
    for (const auto& [j, value] : columns[i]) {
      normal.innerIndexPtr()[at] = j;
      normal.valuePtr()[at] = value;
      ++at;
    }
  }
  normal.outerIndexPtr()[m] = static_cast<int>(at);
  return normal;
}

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
  double mu = 0;
  const Eigen::SparseMatrix<double> normal =
      RegularizedNormalMatrixLower(design, options.regularization, &mu);
  const Eigen::MatrixX3d rhs = design.transpose() * samples + mu * prior;
  return SolveNormalEquations(normal, rhs);
}

Eigen::SparseMatrix<double> RegularizedNormalMatrixLower(
    const DesignMatrix& design, double regularization, double* mu_out) {
  const Eigen::Index m = design.cols();
  Eigen::SparseMatrix<double> normal = NormalMatrixLower(design);
  // The first stored entry of every column is its diagonal.
  double trace = 0.0;
  for (Eigen::Index i = 0; i < m; ++i) {
    trace += normal.valuePtr()[normal.outerIndexPtr()[i]];
  }
  const double mean_diagonal = trace / std::max<Eigen::Index>(m, 1);
  const double mu = regularization * (mean_diagonal > 0 ? mean_diagonal : 1.0);
  for (Eigen::Index i = 0; i < m; ++i) {
    normal.valuePtr()[normal.outerIndexPtr()[i]] += mu;
  }
  if (mu_out != nullptr) *mu_out = mu;
  return normal;
}

StatusOr<Eigen::MatrixX3d> SolveNormalEquations(
    const Eigen::SparseMatrix<double>& lower, const Eigen::MatrixX3d& rhs) {
  if (lower.rows() != lower.cols() || rhs.rows() != lower.rows()) {
    return InvalidArgumentError(
        "least squares: the normal matrix is not square or the right-hand "
        "side's size differs");
  }
  // CHOLMOD's supernodal LL^T (dense BLAS-3 kernels on the supernodes; AMD or
  // METIS ordering, whichever fills less) is 3-4x faster than Eigen's
  // simplicial LDL^T here; the latter stays as the fallback for a matrix
  // that rounding makes indefinite. Both are deterministic.
  {
    const std::lock_guard<std::mutex> blas(BlasMutex());
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower>
        supernodal;
    supernodal.cholmod().print = 0;  // a library does not print
    supernodal.compute(lower);
    if (supernodal.info() == Eigen::Success) {
      Eigen::MatrixX3d c = supernodal.solve(rhs);
      if (supernodal.info() == Eigen::Success && c.allFinite()) return c;
    }
  }
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver(
      lower);
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
