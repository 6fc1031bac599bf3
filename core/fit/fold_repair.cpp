#include "sdcb/core/fit/fold_repair.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <algorithm>
#include <utility>
#include <vector>

#include "sdcb/core/spline/design_matrix.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {

namespace {

// Growth of the folds (over the least seen) at which the repair gives up.
constexpr double kDivergence = 50.0;
// The share of the folds a repair must leave at most to be kept.
constexpr double kKeptFraction = 0.5;

using RowMajor = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// Marks the samples within one lattice ring of a marked one.
void GrowByOneRing(const Eigen::MatrixX3i& triangles, std::vector<char>* mark) {
  std::vector<char> grown = *mark;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    const int a = triangles(t, 0), b = triangles(t, 1), c = triangles(t, 2);
    if ((*mark)[a] || (*mark)[b] || (*mark)[c])
      grown[a] = grown[b] = grown[c] = 1;
  }
  mark->swap(grown);
}

// The columns of `rows` and their neighbours in the symmetric matrix whose
// lower triangle is `lower`, ascending.
std::vector<int> ColumnsNear(const ChartGradientRows& rows,
                             const Eigen::SparseMatrix<double>& lower) {
  const Eigen::Index m = lower.cols();
  std::vector<char> in(m, 0);
  for (const DesignMatrix* d : {&rows.u, &rows.v}) {
    for (Eigen::Index k = 0; k < d->nonZeros(); ++k) {
      in[d->innerIndexPtr()[k]] = 1;
    }
  }
  std::vector<char> near = in;
  for (Eigen::Index j = 0; j < m; ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator e(lower, j); e; ++e) {
      if (in[j] || in[e.row()]) near[j] = near[e.row()] = 1;
    }
  }
  std::vector<int> columns;
  for (Eigen::Index j = 0; j < m; ++j) {
    if (near[j]) columns.push_back(static_cast<int>(j));
  }
  return columns;
}

}  // namespace

StatusOr<FoldRepairResult> RepairFolds(
    const DcbBasis& basis, BasisForm form,
    const Eigen::SparseMatrix<double>& normal_lower, const TriangleMesh& mesh,
    const MeshDistance& mesh_distance, const DeviationOptions& lattice,
    const FoldRepairOptions& options, Eigen::MatrixX3d* control_points) {
  FoldRepairResult result;
  const Eigen::Index m = normal_lower.cols();
  const Eigen::MatrixX3d given = *control_points;
  Eigen::MatrixX3d best = given;
  double least_folded = -1;
  std::vector<char> constrained;
  std::vector<int> samples;  // constrained, in the order they were added
  for (int iteration = 0;; ++iteration) {
    SDCB_ASSIGN_OR_RETURN(
        const SphericalSpline surface,
        SphericalSpline::Create(basis, *control_points, form));
    SDCB_ASSIGN_OR_RETURN(const SurfaceDeviation d,
                          MeasureSurfaceDeviation(surface, mesh, lattice,
                                                  nullptr, &mesh_distance));
    const double folded = d.folded_area_percent;
    result.iterations = iteration;
    if (iteration == 0) result.folded_before_percent = folded;
    if (least_folded < 0 || folded < least_folded) {
      least_folded = folded;
      best = *control_points;
    }
    if (folded == 0 || iteration == options.max_iterations ||
        folded > options.max_folded_percent ||
        folded > kDivergence * least_folded) {
      break;
    }
    // The constrained samples: every one that folded so far, with its
    // lattice ring.
    const Eigen::Index ns = d.surface_sample_points.rows();
    if (constrained.empty()) constrained.assign(ns, 0);
    std::vector<char> mark(ns, 0);
    for (Eigen::Index i = 0; i < ns; ++i) mark[i] = d.surface_sample_folded[i];
    GrowByOneRing(d.surface_sample_triangles, &mark);
    for (Eigen::Index i = 0; i < ns; ++i) {
      if (mark[i] && !constrained[i]) {
        constrained[i] = 1;
        samples.push_back(static_cast<int>(i));
      }
    }
    const int r = static_cast<int>(samples.size());
    Eigen::MatrixX3d points(r, 3);
    for (int s = 0; s < r; ++s) {
      points.row(s) = d.surface_sample_points.row(samples[s]);
    }
    const ChartGradientRows jet = BuildChartGradientRows(basis, points, form);
    const Eigen::MatrixX3d fu = jet.u * *control_points;
    const Eigen::MatrixX3d fv = jet.v * *control_points;

    // The moved control points, their block of N.
    const std::vector<int> columns = ColumnsNear(jet, normal_lower);
    const int ml = static_cast<int>(columns.size());
    std::vector<int> local(m, -1);
    for (int l = 0; l < ml; ++l) local[columns[l]] = l;
    std::vector<Eigen::Triplet<double>> entries;
    Eigen::VectorXd diagonal(ml);
    for (int l = 0; l < ml; ++l) {
      for (Eigen::SparseMatrix<double>::InnerIterator e(normal_lower,
                                                        columns[l]);
           e; ++e) {
        const int row = local[e.row()];
        if (row < 0) continue;
        if (row == l) diagonal[l] = e.value();
        for (int c = 0; c < 3; ++c) {
          entries.emplace_back(3 * row + c, 3 * l + c, e.value());
        }
      }
    }

    // The linearized constraints J d >= t - g, one row per sample.
    std::vector<Eigen::Triplet<double>> j_entries;
    Eigen::VectorXd shortfall(r);
    for (int s = 0; s < r; ++s) {
      const Eigen::Vector3d n =
          mesh_distance.FaceNormal(d.surface_sample_mesh_face[samples[s]]);
      const Eigen::Vector3d a = fu.row(s).transpose(),
                            b = fv.row(s).transpose();
      const double g = a.cross(b).dot(n);
      shortfall[s] =
          std::min(0.0, g - options.normal_floor * a.norm() * b.norm());
      const Eigen::Vector3d along_u = b.cross(n), along_v = n.cross(a);
      for (DesignMatrix::InnerIterator e(jet.u, s); e; ++e) {
        for (int c = 0; c < 3; ++c) {
          j_entries.emplace_back(s, 3 * local[e.col()] + c,
                                 e.value() * along_u[c]);
        }
      }
      for (DesignMatrix::InnerIterator e(jet.v, s); e; ++e) {
        for (int c = 0; c < 3; ++c) {
          j_entries.emplace_back(s, 3 * local[e.col()] + c,
                                 e.value() * along_v[c]);
        }
      }
    }
    RowMajor jacobian(r, 3 * ml);
    jacobian.setFromTriplets(j_entries.begin(), j_entries.end());
    Eigen::VectorXd weight(r);
    for (int s = 0; s < r; ++s) {
      double scale = 0;
      for (RowMajor::InnerIterator e(jacobian, s); e; ++e) {
        scale += e.value() * e.value() / diagonal[e.col() / 3];
      }
      weight[s] = scale > 0 ? 1.0 / (options.damping * scale) : 0.0;
    }
    Eigen::SparseMatrix<double> system(3 * ml, 3 * ml);
    system.setFromTriplets(entries.begin(), entries.end());
    const Eigen::SparseMatrix<double> weighted_t =
        Eigen::SparseMatrix<double>(jacobian.transpose()) * weight.asDiagonal();
    const Eigen::SparseMatrix<double> penalty =
        (weighted_t * jacobian).triangularView<Eigen::Lower>();
    system += penalty;
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower>
        factor;
    factor.cholmod().print = 0;  // a library does not print
    factor.compute(system);
    if (factor.info() != Eigen::Success) {
      return InternalError("fold repair: the factorization failed");
    }
    const Eigen::VectorXd step =
        factor.solve(Eigen::VectorXd(-(weighted_t * shortfall)));
    if (factor.info() != Eigen::Success || !step.allFinite()) {
      return InternalError("fold repair: the solve failed");
    }
    for (int l = 0; l < ml; ++l) {
      for (int c = 0; c < 3; ++c) {
        (*control_points)(columns[l], c) += step[3 * l + c];
      }
    }
    result.moved_control_points = std::max(result.moved_control_points, ml);
    result.constrained_samples = r;
  }
  // Kept when the folds at least halved, else the given control points.
  result.changed = result.iterations > 0 &&
                   least_folded <= kKeptFraction * result.folded_before_percent;
  if (result.changed) {
    *control_points = std::move(best);
    result.folded_after_percent = least_folded;
  } else {
    *control_points = given;
    result.folded_after_percent = result.folded_before_percent;
    result.moved_control_points = 0;
  }
  return result;
}

}  // namespace sdcb
