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

// The factor a dropped step multiplies the damping by (and a taken one
// divides it by, down to the option's).
constexpr double kDampingFactor = 4.0;
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
  SDCB_ASSIGN_OR_RETURN(const SphericalSpline spline,
                        SphericalSpline::Create(basis, given, form));
  SDCB_ASSIGN_OR_RETURN(
      SurfaceDeviation d,
      MeasureSurfaceDeviation(spline, mesh, lattice, nullptr, &mesh_distance));
  result.folded_before_percent = d.folded_area_percent;
  if (d.folded_area_percent == 0 ||
      d.folded_area_percent > options.max_folded_percent) {
    result.folded_after_percent = result.folded_before_percent;
    return result;
  }
  const double max_distance =
      std::max(d.surface_to_mesh_max_percent, options.max_distance_percent);
  const DesignMatrix lattice_values =
      BuildFormDesignMatrix(basis, d.surface_sample_points, form);
  const Eigen::Index ns = d.surface_sample_points.rows();
  std::vector<char> constrained(ns, 0);
  std::vector<int> samples;  // constrained, in the order they were added
  // Constrains the folded samples of `measured` and their lattice ring.
  const auto constrain_folds = [&](const SurfaceDeviation& measured) {
    std::vector<char> mark(ns, 0);
    for (Eigen::Index i = 0; i < ns; ++i) {
      mark[i] = measured.surface_sample_folded[i];
    }
    GrowByOneRing(measured.surface_sample_triangles, &mark);
    for (Eigen::Index i = 0; i < ns; ++i) {
      if (mark[i] && !constrained[i]) {
        constrained[i] = 1;
        samples.push_back(static_cast<int>(i));
      }
    }
  };
  constrain_folds(d);
  double damping = options.damping;
  while (result.iterations < options.max_iterations) {
    const int r = static_cast<int>(samples.size());
    Eigen::MatrixX3d points(r, 3);
    std::vector<Eigen::Vector3d> normals(r);
    for (int s = 0; s < r; ++s) {
      points.row(s) = d.surface_sample_points.row(samples[s]);
      MeshDistance::Closest closest;
      closest.face = d.surface_sample_mesh_face[samples[s]];
      closest.point = d.surface_sample_mesh_point.row(samples[s]).transpose();
      normals[s] = mesh_distance.Normal(closest);
    }
    const ChartGradientRows jet = BuildChartGradientRows(basis, points, form);
    // min(0, g - floor |F_u| |F_v|) at the constrained samples for the
    // control points x.
    const auto shortfall_at = [&](const Eigen::MatrixX3d& x) {
      const Eigen::MatrixX3d fu = jet.u * x, fv = jet.v * x;
      Eigen::VectorXd shortfall(r);
      for (int s = 0; s < r; ++s) {
        const Eigen::Vector3d a = fu.row(s).transpose(),
                              b = fv.row(s).transpose();
        shortfall[s] =
            std::min(0.0, a.cross(b).dot(normals[s]) -
                              options.normal_floor * a.norm() * b.norm());
      }
      return shortfall;
    };
    const Eigen::VectorXd shortfall = shortfall_at(*control_points);
    // Done when nothing folds and every constrained sample has its margin
    // (a sample between the lattice's may still turn over before that).
    if (d.folded_area_percent == 0 && shortfall.isZero(0)) break;
    ++result.iterations;
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
    for (int s = 0; s < r; ++s) {
      const Eigen::Vector3d& n = normals[s];
      const Eigen::Vector3d a = fu.row(s).transpose(),
                            b = fv.row(s).transpose();
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
      weight[s] = scale > 0 ? 1.0 / (damping * scale) : 0.0;
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
    Eigen::MatrixX3d trial = *control_points;
    for (int l = 0; l < ml; ++l) {
      for (int c = 0; c < 3; ++c) trial(columns[l], c) += step[3 * l + c];
    }
    SDCB_ASSIGN_OR_RETURN(const SphericalSpline moved,
                          SphericalSpline::Create(basis, trial, form));
    SurfaceDeviation measured = d;
    SDCB_RETURN_IF_ERROR(RemeasureSurfaceToMesh(
        moved, mesh_distance, lattice, lattice_values, columns, &measured));
    result.constrained_samples = r;
    // A step that keeps the surface within the distance and folds less, or
    // as much with less shortfall, is taken, and the next may be longer;
    // else it is dropped and the next is shorter. Either way the samples it
    // folded are constrained from then on.
    const bool better =
        measured.folded_area_percent < d.folded_area_percent ||
        (measured.folded_area_percent == d.folded_area_percent &&
         shortfall_at(trial).squaredNorm() < shortfall.squaredNorm());
    constrain_folds(measured);
    if (better && measured.surface_to_mesh_max_percent <= max_distance) {
      *control_points = std::move(trial);
      d = std::move(measured);
      damping = std::max(options.damping, damping / kDampingFactor);
      result.moved_control_points = std::max(result.moved_control_points, ml);
    } else {
      damping *= kDampingFactor;
    }
  }
  // Kept when the folds at least halved, else the given control points.
  result.changed =
      d.folded_area_percent <= kKeptFraction * result.folded_before_percent;
  if (result.changed) {
    result.folded_after_percent = d.folded_area_percent;
  } else {
    *control_points = given;
    result.folded_after_percent = result.folded_before_percent;
    result.moved_control_points = 0;
  }
  return result;
}

}  // namespace sdcb
