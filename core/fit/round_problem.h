// A round's regularized least-squares problem (paper Sec. 4.5): the DCB
// basis on the round's knots, the data term's samples of the mesh and its
// design matrix, and the bending energy's rows at a quadrature of the knot
// triangles; and its solution, the control points.
#ifndef SDCB_CORE_FIT_ROUND_PROBLEM_H_
#define SDCB_CORE_FIT_ROUND_PROBLEM_H_

#include <Eigen/Core>

#include "sdcb/core/common/status.h"
#include "sdcb/core/fit/fit_mesh.h"
#include "sdcb/core/fit/fit_options.h"
#include "sdcb/core/fit/fit_result.h"
#include "sdcb/core/fit/fit_samples.h"
#include "sdcb/core/mesh/feature_curves.h"
#include "sdcb/core/spline/dcb_basis.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/core/spline/design_matrix.h"

namespace sdcb {

// The bending energy's quadrature: three points per knot triangle (the
// degree-2 planar rule at barycentric (2/3, 1/6, 1/6) and permutations,
// mapped onto the sphere), each weighted a third of the spherical area.
struct BendingQuadrature {
  Eigen::MatrixX3d points;
  Eigen::VectorXd weights;
};

// The round's least-squares problem: the basis on the round's knots, the data
// term's samples and design matrix, and the bending rows.
struct RoundProblem {
  DcbBasis basis;
  FitSamples samples;
  DesignMatrix data;
  BendingQuadrature bending;
  ChartHessianRows hessian;

  // Eigen 3.4's sparse matrices have no move constructor: moving a RoundProblem
  // (into and out of its StatusOr) swaps them instead of copying.
  RoundProblem(DcbBasis b, FitSamples s, DesignMatrix* d, BendingQuadrature q,
               ChartHessianRows* h)
      : basis(std::move(b)), samples(std::move(s)), bending(std::move(q)) {
    SwapMatrices(d, h);
  }
  RoundProblem(RoundProblem&& other) noexcept
      : basis(std::move(other.basis)),
        samples(std::move(other.samples)),
        bending(std::move(other.bending)) {
    SwapMatrices(&other.data, &other.hessian);
  }
  void SwapMatrices(DesignMatrix* d, ChartHessianRows* h) {
    data.swap(*d);
    hessian.uu.swap(h->uu);
    hessian.uv.swap(h->uv);
    hessian.vv.swap(h->vv);
  }
};

// The problem on `knots`: the basis on their degree-k `configurations`
// (kInvalidInput when it has a hole: a knot outside every support), the
// data term's samples spaced by the knots, and the bending rows at the
// quadrature of `knot_triangles` (their degree-0 configurations).
// `features`: the mesh's, for a round on the feature corners' clusters
// (core/fit/feature_round.h), whose samples are spaced by the corners alone
// and pinned by rows beside the feature edges; null otherwise. `details`
// gets the samples' counts.
StatusOr<RoundProblem> BuildRoundProblem(
    const FitOptions& options, const FitMesh& fit,
    const Eigen::MatrixX3d& knots, const DelaunayConfigurations& configurations,
    const DelaunayConfigurations& knot_triangles, const MeshFeatures* features,
    RoundDetails* details);

// The least squares' rows (the data term's and the bending energy's),
// scaled by the square roots of their weights.
DesignMatrix StackedDesign(const FitOptions& options, const FitMesh& fit,
                           const RoundProblem& problem);

// The control points: the regularized least-squares solution, its prior
// the Greville prior of the samples nearest to each basis function.
StatusOr<Eigen::MatrixX3d> SolveRoundProblem(const FitOptions& options,
                                             const FitMesh& fit,
                                             const RoundProblem& problem);

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_ROUND_PROBLEM_H_
