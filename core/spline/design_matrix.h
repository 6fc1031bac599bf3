// The least-squares design matrix of the spherical DCB-spline (paper eq. 6):
// A(r, i) = Bbar_i(u_r), rows = parameter points u_r, columns = basis
// functions, so that F(u_r) = (A C)(r, :) for control points C (#basis by 3).
#ifndef SDCB_CORE_SPLINE_DESIGN_MATRIX_H_
#define SDCB_CORE_SPLINE_DESIGN_MATRIX_H_

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <utility>
#include <vector>

#include "sdcb/core/spline/dcb_basis.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

using DesignMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

struct DesignMatrixOptions {
  // true: Bbar_i = B_i / I (eq. 5, the surface's basis). false: the raw B_i
  // of eq. 4 (for studies of the unnormalized spline space).
  bool normalized = true;
};

// `points`: #P by 3 unit vectors. Returns the #P by basis.size() matrix of
// basis values, only nonzeros stored, columns ascending in each row; with
// normalization, rows sum to 1 up to rounding. Parallel (TBB); the result
// does not depend on the number of threads.
DesignMatrix BuildDesignMatrix(const DcbBasis& basis,
                               const Eigen::MatrixX3d& points,
                               const DesignMatrixOptions& options = {});

// The raw (eq. 4) design matrix, reusing a previous round's values: when
// basis function i is identical to column previous_columns[i] (>= 0) of
// `previous` — same knot coordinates, same boundary triples, so the same
// function — its values are copied from `previous` (computed at the same
// `points`) instead of evaluated. The result is bit-identical to
// BuildDesignMatrix(basis, points, {.normalized = false}). `previous` may be
// null (nothing reused); else previous_columns has basis.size() entries.
DesignMatrix BuildRawDesignMatrix(
    const DcbBasis& basis, const Eigen::MatrixX3d& points,
    const DesignMatrix* previous = nullptr,
    const std::vector<int>* previous_columns = nullptr);

// Divides every row by its sum (eq. 5: Bbar = B / I), summing in column
// order: NormalizeRows(raw) is bit-identical to the normalized
// BuildDesignMatrix on the same basis and points.
DesignMatrix NormalizeRows(const DesignMatrix& raw);

// The design matrix of the surface's basis b_i (BasisForm::kNormalized:
// Bbar_i, eq. 5; kRaw: B_i, eq. 4) at `points` (#P by 3 unit vectors).
DesignMatrix BuildFormDesignMatrix(const DcbBasis& basis,
                                   const Eigen::MatrixX3d& points,
                                   BasisForm form);

// Second derivatives of the surface's basis functions in the tangent chart
// of core/spline/spherical_spline.h (phi(u, v) = b(p + u e_u + v e_v), the
// basis extended homogeneously of degree 0; at p the chart's second
// derivatives are the covariant Hessian on S^2): row r of `uu`, `uv`, `vv`
// holds d2 b_i / du2, d2 b_i / du dv, d2 b_i / dv2 at points.row(r) for every
// basis function i that is nonzero near it. The fitting's bending energy is
// assembled from them. Parallel; independent of the thread count.
struct ChartHessianRows {
  DesignMatrix uu, uv, vv;
};
ChartHessianRows BuildChartHessianRows(const DcbBasis& basis,
                                       const Eigen::MatrixX3d& points,
                                       BasisForm form);

// First derivatives in the same chart: row r of `u` and `v` holds
// d b_i / du and d b_i / dv at points.row(r), in the frame
// TangentFrame(points.row(r)).
struct ChartGradientRows {
  DesignMatrix u, v;
};
ChartGradientRows BuildChartGradientRows(const DcbBasis& basis,
                                         const Eigen::MatrixX3d& points,
                                         BasisForm form);

// The rows of `parts` one below the other, each row r of a part scaled by
// (*scale)[r] (a null scale: the rows as they are).
DesignMatrix StackScaledRows(
    const std::vector<std::pair<const DesignMatrix*, const Eigen::VectorXd*>>&
        parts);

}  // namespace sdcb

#endif  // SDCB_CORE_SPLINE_DESIGN_MATRIX_H_
