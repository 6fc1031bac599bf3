#include "sdcb/core/fit/fold_repair.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <algorithm>
#include <optional>
#include <utility>
#include <vector>

#include "sdcb/core/common/blas_lock.h"
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

// The lattice samples the repair constrains: the folded ones and their
// lattice ring (in the kept region of a trimmed surface), in the order they
// were added.
class ConstrainedSamples {
 public:
  explicit ConstrainedSamples(Eigen::Index lattice_samples)
      : constrained_(lattice_samples, 0) {}

  // Constrains the folded samples of `measured` and their lattice ring.
  void AddFolds(const SurfaceDeviation& measured) {
    const Eigen::Index ns = static_cast<Eigen::Index>(constrained_.size());
    std::vector<char> mark(ns, 0);
    for (Eigen::Index i = 0; i < ns; ++i) {
      mark[i] = measured.surface_sample_folded[i];
    }
    GrowByOneRing(measured.surface_sample_triangles, &mark);
    // Outside a trimmed surface's kept region nothing was measured (no
    // closest point): nothing to constrain.
    const std::vector<bool>& kept = measured.surface_sample_kept;
    for (Eigen::Index i = 0; i < ns; ++i) {
      if (!kept.empty() && !kept[i]) mark[i] = 0;
    }
    for (Eigen::Index i = 0; i < ns; ++i) {
      if (mark[i] && !constrained_[i]) {
        constrained_[i] = 1;
        samples_.push_back(static_cast<int>(i));
      }
    }
  }

  const std::vector<int>& samples() const { return samples_; }

 private:
  std::vector<char> constrained_;
  std::vector<int> samples_;
};

// g's pieces at the constrained samples: the chart derivatives' rows and
// the mesh's normal at each sample's closest point.
struct Linearization {
  ChartGradientRows jet;
  std::vector<Eigen::Vector3d> normals;

  // min(0, g - floor |F_u| |F_v|) at the constrained samples for the
  // control points x.
  Eigen::VectorXd Shortfall(const Eigen::MatrixX3d& x, double floor) const {
    const Eigen::MatrixX3d fu = jet.u * x, fv = jet.v * x;
    const int r = static_cast<int>(normals.size());
    Eigen::VectorXd shortfall(r);
    for (int s = 0; s < r; ++s) {
      const Eigen::Vector3d a = fu.row(s).transpose(),
                            b = fv.row(s).transpose();
      shortfall[s] = std::min(
          0.0, a.cross(b).dot(normals[s]) - floor * a.norm() * b.norm());
    }
    return shortfall;
  }
};

// Brings `l` to the constrained `samples` of `d` (those of the last call
// first, in the same order): the chart derivatives' rows of the samples
// added since (a row depends only on its sample's point, which stays), and
// every sample's normal at its closest point on the mesh now.
void Relinearize(const DcbBasis& basis, BasisForm form,
                 const MeshDistance& mesh_distance, const SurfaceDeviation& d,
                 const std::vector<int>& samples, Linearization* l) {
  const int r = static_cast<int>(samples.size());
  const int known = static_cast<int>(l->jet.u.rows());
  if (r > known) {
    Eigen::MatrixX3d points(r - known, 3);
    for (int s = known; s < r; ++s) {
      points.row(s - known) = d.surface_sample_points.row(samples[s]);
    }
    ChartGradientRows added = BuildChartGradientRows(basis, points, form);
    if (known == 0) {
      l->jet = std::move(added);
    } else {
      l->jet.u = StackScaledRows({{&l->jet.u, nullptr}, {&added.u, nullptr}});
      l->jet.v = StackScaledRows({{&l->jet.v, nullptr}, {&added.v, nullptr}});
    }
  }
  l->normals.resize(r);
  for (int s = 0; s < r; ++s) {
    MeshDistance::Closest closest;
    closest.face = d.surface_sample_mesh_face[samples[s]];
    closest.point = d.surface_sample_mesh_point.row(samples[s]).transpose();
    l->normals[s] = mesh_distance.Normal(closest);
  }
}

// The block of N (the normal matrix whose lower triangle is `lower`) of
// the moved control points `columns` (`local`: their index in the block,
// -1 for the others), each entry repeated for the 3 coordinates; and the
// diagonal of that block.
Eigen::SparseMatrix<double> MovedBlock(const Eigen::SparseMatrix<double>& lower,
                                       const std::vector<int>& columns,
                                       const std::vector<int>& local,
                                       Eigen::VectorXd* diagonal) {
  const int ml = static_cast<int>(columns.size());
  std::vector<Eigen::Triplet<double>> entries;
  diagonal->resize(ml);
  for (int l = 0; l < ml; ++l) {
    for (Eigen::SparseMatrix<double>::InnerIterator e(lower, columns[l]); e;
         ++e) {
      const int row = local[e.row()];
      if (row < 0) continue;
      if (row == l) (*diagonal)[l] = e.value();
      for (int c = 0; c < 3; ++c) {
        entries.emplace_back(3 * row + c, 3 * l + c, e.value());
      }
    }
  }
  Eigen::SparseMatrix<double> system(3 * ml, 3 * ml);
  system.setFromTriplets(entries.begin(), entries.end());
  return system;
}

// The linearized constraints J d >= t - g, one row per sample, in the
// moved control points' coordinates (`local`, `ml` of them) at
// `control_points`.
RowMajor ConstraintJacobian(const Linearization& lin,
                            const Eigen::MatrixX3d& control_points,
                            const std::vector<int>& local, int ml) {
  const Eigen::MatrixX3d fu = lin.jet.u * control_points;
  const Eigen::MatrixX3d fv = lin.jet.v * control_points;
  const int r = static_cast<int>(lin.normals.size());
  std::vector<Eigen::Triplet<double>> j_entries;
  for (int s = 0; s < r; ++s) {
    const Eigen::Vector3d& n = lin.normals[s];
    const Eigen::Vector3d a = fu.row(s).transpose(), b = fv.row(s).transpose();
    const Eigen::Vector3d along_u = b.cross(n), along_v = n.cross(a);
    for (DesignMatrix::InnerIterator e(lin.jet.u, s); e; ++e) {
      for (int c = 0; c < 3; ++c) {
        j_entries.emplace_back(s, 3 * local[e.col()] + c,
                               e.value() * along_u[c]);
      }
    }
    for (DesignMatrix::InnerIterator e(lin.jet.v, s); e; ++e) {
      for (int c = 0; c < 3; ++c) {
        j_entries.emplace_back(s, 3 * local[e.col()] + c,
                               e.value() * along_v[c]);
      }
    }
  }
  RowMajor jacobian(r, 3 * ml);
  jacobian.setFromTriplets(j_entries.begin(), j_entries.end());
  return jacobian;
}

// The Cholesky factor of the steps' systems. Its ordering (the symbolic
// analysis) is kept while their pattern stays: each factor is the one a
// fresh analysis would give, without redoing it.
class StepFactor {
 public:
  StepFactor() { factor_.cholmod().print = 0; }  // a library does not print

  // Factors `system` (lower triangle); false if that fails.
  bool Factorize(const Eigen::SparseMatrix<double>& system) {
    const Eigen::Index n = system.cols();
    const bool same_pattern =
        analyzed_ && n == static_cast<Eigen::Index>(outer_.size()) - 1 &&
        std::equal(outer_.begin(), outer_.end(), system.outerIndexPtr()) &&
        system.nonZeros() == static_cast<Eigen::Index>(inner_.size()) &&
        std::equal(inner_.begin(), inner_.end(), system.innerIndexPtr());
    if (!same_pattern) {
      factor_.analyzePattern(system);
      analyzed_ = factor_.info() == Eigen::Success;
      if (!analyzed_) return false;
      outer_.assign(system.outerIndexPtr(), system.outerIndexPtr() + n + 1);
      inner_.assign(system.innerIndexPtr(),
                    system.innerIndexPtr() + system.nonZeros());
    }
    factor_.factorize(system);
    return factor_.info() == Eigen::Success;
  }

  // x with system x = b for the system last factored; nullopt if the solve
  // fails.
  std::optional<Eigen::VectorXd> Solve(const Eigen::VectorXd& b) {
    Eigen::VectorXd x = factor_.solve(b);
    if (factor_.info() != Eigen::Success || !x.allFinite()) return std::nullopt;
    return x;
  }

 private:
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower>
      factor_;
  bool analyzed_ = false;
  std::vector<int> outer_, inner_;
};

// One step: the control points `columns` (the others fixed) moved by the
// d that minimizes d^T (N (x) I_3) d + sum_s w_s (g_s + J_s d - t_s)^2, the
// weights damped by `damping` (fold_repair.h). kInternal if the
// factorization or the solve fails.
StatusOr<Eigen::MatrixX3d> TrialStep(
    const Linearization& lin, const Eigen::SparseMatrix<double>& normal_lower,
    const std::vector<int>& columns, const Eigen::VectorXd& shortfall,
    double damping, const Eigen::MatrixX3d& control_points,
    StepFactor* factor) {
  const Eigen::Index m = normal_lower.cols();
  const int r = static_cast<int>(lin.normals.size());
  // The moved control points, their block of N.
  const int ml = static_cast<int>(columns.size());
  std::vector<int> local(m, -1);
  for (int l = 0; l < ml; ++l) local[columns[l]] = l;
  Eigen::VectorXd diagonal;
  Eigen::SparseMatrix<double> system =
      MovedBlock(normal_lower, columns, local, &diagonal);
  const RowMajor jacobian = ConstraintJacobian(lin, control_points, local, ml);
  Eigen::VectorXd weight(r);
  for (int s = 0; s < r; ++s) {
    double scale = 0;
    for (RowMajor::InnerIterator e(jacobian, s); e; ++e) {
      scale += e.value() * e.value() / diagonal[e.col() / 3];
    }
    weight[s] = scale > 0 ? 1.0 / (damping * scale) : 0.0;
  }
  const Eigen::SparseMatrix<double> weighted_t =
      Eigen::SparseMatrix<double>(jacobian.transpose()) * weight.asDiagonal();
  const Eigen::SparseMatrix<double> penalty =
      (weighted_t * jacobian).triangularView<Eigen::Lower>();
  system += penalty;
  system.makeCompressed();
  const std::lock_guard<std::mutex> blas(BlasMutex());
  if (!factor->Factorize(system)) {
    return InternalError("fold repair: the factorization failed");
  }
  const std::optional<Eigen::VectorXd> solved =
      factor->Solve(Eigen::VectorXd(-(weighted_t * shortfall)));
  if (!solved) return InternalError("fold repair: the solve failed");
  const Eigen::VectorXd& step = *solved;
  Eigen::MatrixX3d trial = control_points;
  for (int l = 0; l < ml; ++l) {
    for (int c = 0; c < 3; ++c) trial(columns[l], c) += step[3 * l + c];
  }
  return trial;
}

}  // namespace

StatusOr<FoldRepairResult> RepairFolds(
    const DcbBasis& basis, BasisForm form,
    const Eigen::SparseMatrix<double>& normal_lower, const TriangleMesh& mesh,
    const MeshDistance& mesh_distance, const DeviationOptions& lattice,
    const FoldRepairOptions& options, Eigen::MatrixX3d* control_points) {
  FoldRepairResult result;
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
  ConstrainedSamples constrained(d.surface_sample_points.rows());
  constrained.AddFolds(d);
  double damping = options.damping;
  Linearization lin;
  StepFactor factor;
  while (result.iterations < options.max_iterations) {
    Relinearize(basis, form, mesh_distance, d, constrained.samples(), &lin);
    const Eigen::VectorXd shortfall =
        lin.Shortfall(*control_points, options.normal_floor);
    // Done when nothing folds and every constrained sample has its margin
    // (a sample between the lattice's may still turn over before that).
    if (d.folded_area_percent == 0 && shortfall.isZero(0)) break;
    ++result.iterations;
    const std::vector<int> columns = ColumnsNear(lin.jet, normal_lower);
    SDCB_ASSIGN_OR_RETURN(Eigen::MatrixX3d trial,
                          TrialStep(lin, normal_lower, columns, shortfall,
                                    damping, *control_points, &factor));
    SDCB_ASSIGN_OR_RETURN(const SphericalSpline moved,
                          SphericalSpline::Create(basis, trial, form));
    SurfaceDeviation measured = d;
    SDCB_RETURN_IF_ERROR(RemeasureSurfaceToMesh(
        moved, mesh_distance, lattice, lattice_values, columns, &measured));
    result.constrained_samples = static_cast<int>(lin.normals.size());
    // A step that keeps the surface within the distance and folds less, or
    // as much with less shortfall, is taken, and the next may be longer;
    // else it is dropped and the next is shorter. Either way the samples it
    // folded are constrained from then on.
    const bool better =
        measured.folded_area_percent < d.folded_area_percent ||
        (measured.folded_area_percent == d.folded_area_percent &&
         lin.Shortfall(trial, options.normal_floor).squaredNorm() <
             shortfall.squaredNorm());
    constrained.AddFolds(measured);
    if (better && measured.surface_to_mesh_max_percent <= max_distance) {
      *control_points = std::move(trial);
      d = std::move(measured);
      damping = std::max(options.damping, damping / kDampingFactor);
      result.moved_control_points = std::max(result.moved_control_points,
                                             static_cast<int>(columns.size()));
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
