#include "sdcb/core/fit/adaptive_fit.h"

#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "sdcb/core/fit/least_squares.h"
#include "sdcb/core/knots/spherical_cvt.h"
#include "sdcb/core/mesh/curvature.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/param/spherical_parameterization.h"
#include "sdcb/core/sphere/point_kd_tree.h"
#include "sdcb/core/spline/dcb_basis.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/core/spline/design_matrix.h"

namespace sdcb {
namespace {

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double Seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         start_)
        .count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

Status CheckOptions(const FitOptions& o) {
  if (o.degree < 2 || o.degree > kMaxSplineDegree) {
    return InvalidArgumentError("degree must be 2..5");
  }
  if (!(o.rmse_percent > 0) || !std::isfinite(o.rmse_percent)) {
    return InvalidArgumentError(
        "the RMSE target must be a positive percentage");
  }
  if (o.knots_per_round < 1 || o.initial_knots < 0 || o.max_rounds < 1 ||
      o.max_control_points < 1) {
    return InvalidArgumentError(
        "knots per round, rounds and control points must be positive");
  }
  if (!(o.alpha > 0) || !(o.regularization > 0) || !(o.lambda > 0) ||
      !(o.face_weight > 0)) {
    return InvalidArgumentError(
        "alpha, lambda, regularization and face weight must be > 0");
  }
  return Status::Ok();
}

// For every basis function, the sample nearest to the normalized mean of its
// knots: the prior of basis functions that no sample sees.
Eigen::MatrixX3d NearestSamplePrior(const DcbBasis& basis,
                                    const PointKdTree& tree,
                                    const Eigen::MatrixX3d& samples) {
  Eigen::MatrixX3d prior(basis.size(), 3);
  for (int i = 0; i < basis.size(); ++i) {
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    for (int k : basis.configuration_set(i).knots) {
      center += basis.knots().row(k).transpose();
    }
    const PointKdTree::Neighbor n = tree.Nearest(center.normalized());
    prior.row(i) = samples.row(n.index >= 0 ? n.index : 0);
  }
  return prior;
}

// The rows of `top` followed by the rows of `bottom` (same column count).
DesignMatrix StackRows(const DesignMatrix& top, const DesignMatrix& bottom) {
  DesignMatrix out(top.rows() + bottom.rows(), top.cols());
  out.resizeNonZeros(top.nonZeros() + bottom.nonZeros());
  Eigen::Index at = 0, row = 0;
  for (const DesignMatrix* part : {&top, &bottom}) {
    for (Eigen::Index r = 0; r < part->rows(); ++r, ++row) {
      out.outerIndexPtr()[row] = static_cast<int>(at);
      for (DesignMatrix::InnerIterator it(*part, r); it; ++it, ++at) {
        out.innerIndexPtr()[at] = static_cast<int>(it.col());
        out.valuePtr()[at] = it.value();
      }
    }
  }
  out.outerIndexPtr()[row] = static_cast<int>(at);
  return out;
}

// Identifies a basis function across rounds: its knot indices, then its
// boundary triples (knot indices are stable: fixed knots keep their rows).
std::vector<int> BasisKey(const ConfigurationSet& set) {
  std::vector<int> key = set.knots;
  key.push_back(-1);
  for (const auto& b : set.boundaries)
    key.insert(key.end(), b.begin(), b.end());
  return key;
}

}  // namespace

StatusOr<FitResult> FitSphericalSpline(const TriangleMesh& mesh,
                                       const FitOptions& options) {
  SDCB_RETURN_IF_ERROR(CheckOptions(options));
  SDCB_RETURN_IF_ERROR(RequireClosedGenusZero(mesh));
  std::unique_ptr<tbb::global_control> thread_limit;
  if (options.threads > 0) {
    thread_limit = std::make_unique<tbb::global_control>(
        tbb::global_control::max_allowed_parallelism, options.threads);
  }
  const Stopwatch total;
  auto report = [&](const std::string& stage, double fraction) {
    if (options.progress) options.progress(stage, std::min(1.0, fraction));
  };

  FitResult result;
  SplineModel& model = result.model;
  model.degree = options.degree;
  SDCB_ASSIGN_OR_RETURN(model.transform, ComputeNormalizingTransform(mesh));
  const Eigen::MatrixX3d samples = model.transform.ToNormalized(mesh.vertices);
  model.source.num_vertices = mesh.num_vertices();
  model.source.num_faces = mesh.num_faces();
  model.source.hash = HashTriangleMesh(mesh);
  FitStatistics& stats = model.statistics;
  stats.options = {options.degree, options.rmse_percent,
                   options.knots_per_round, options.max_rounds, options.lambda};

  // 1. Spherical parameterization (Sec. 4.3).
  report("parameterization", 0.0);
  Stopwatch stage;
  SphericalParameterizationOptions param_options;
  param_options.lambda = options.lambda;
  param_options.threads = options.threads;
  param_options.progress = [&](const std::string&, double f) {
    report("parameterization", 0.3 * f);
  };
  SDCB_ASSIGN_OR_RETURN(const SphericalParameterization param,
                        ParameterizeOnSphere(mesh, param_options));
  const Eigen::MatrixX3d& u = param.sphere;
  stats.timings.parameterization = stage.Seconds();
  // Optional least-squares rows of the piecewise-linear surface: triangle
  // centroids (parameter: normalized sum of the corners' sphere points).
  const Eigen::Index nf = options.face_samples ? mesh.num_faces() : 0;
  Eigen::MatrixX3d face_points(nf, 3), all_targets(mesh.num_vertices() + nf, 3);
  all_targets.topRows(mesh.num_vertices()) = samples;
  for (Eigen::Index f = 0; f < nf; ++f) {
    Eigen::RowVector3d p = Eigen::RowVector3d::Zero(), x = p;
    for (int k = 0; k < 3; ++k) {
      p += u.row(mesh.faces(f, k));
      x += samples.row(mesh.faces(f, k));
    }
    face_points.row(f) = p.normalized();
    all_targets.row(mesh.num_vertices() + f) =
        std::sqrt(options.face_weight) * x / 3.0;
  }
  const PointKdTree parameter_tree(u);

  // Control points for `design` (vertex rows first) and its targets, and the
  // errors at the vertices in percent of the largest side (normalized frame:
  // side 1).
  struct Solution {
    Eigen::MatrixX3d control_points;
    Eigen::VectorXd errors;
    double rmse = 0, max = 0;
  };
  // `fallback`: NearestSamplePrior of the basis, computed once per basis.
  auto solve = [&](const DesignMatrix& design, const Eigen::MatrixX3d& targets,
                   const Eigen::MatrixX3d& fallback) -> StatusOr<Solution> {
    const Eigen::MatrixX3d prior = GrevillePrior(design, targets, fallback);
    LeastSquaresOptions ls;
    ls.regularization = options.regularization;
    Solution s;
    SDCB_ASSIGN_OR_RETURN(s.control_points, SolveRegularizedLeastSquares(
                                                design, targets, prior, ls));
    const Eigen::MatrixX3d fitted =
        design.topRows(samples.rows()) * s.control_points;
    s.errors = 100.0 * (fitted - samples).rowwise().norm();
    s.rmse = std::sqrt(s.errors.squaredNorm() / s.errors.size());
    s.max = s.errors.maxCoeff();
    return s;
  };
  // The same fit with the triangle-centroid rows added.
  // Adds the seconds spent on the centroid rows' basis values and on the
  // solve to `timings`.
  auto solve_with_faces = [&](const DcbBasis& basis,
                              const DesignMatrix& vertex_design,
                              const Eigen::MatrixX3d& fallback,
                              StageTimings* timings) -> StatusOr<Solution> {
    Stopwatch clock;
    const double root_weight = std::sqrt(options.face_weight);
    const DesignMatrix design = StackRows(
        vertex_design,
        root_weight * NormalizeRows(BuildRawDesignMatrix(basis, face_points)));
    timings->basis += clock.Seconds();
    clock = Stopwatch();
    StatusOr<Solution> s = solve(design, all_targets, fallback);
    timings->solve += clock.Seconds();
    return s;
  };

  // 2. Round-0 density: curvedness^alpha (Sec. 4.4).
  stage = Stopwatch();
  SDCB_ASSIGN_OR_RETURN(Eigen::VectorXd curvedness, Curvedness(mesh));
  if (!(curvedness.maxCoeff() > 0)) curvedness.setOnes();  // flat: uniform
  SphericalDensity density{u, mesh.faces, Eigen::VectorXd()};
  SDCB_ASSIGN_OR_RETURN(density.values,
                        DensityFromValues(curvedness, options.alpha));
  stats.timings.knot_placement += stage.Seconds();

  // 3. Rounds. Intermediate rounds fit the vertices only (their solutions
  // only steer the next knots); a round whose vertex fit reaches the target,
  // or the last one, is refitted with the centroid rows, and that is the
  // model returned.
  Eigen::MatrixX3d knots(0, 3);
  CvtOptions cvt;
  DesignMatrix previous_raw;                      // last round's raw B values
  std::map<std::vector<int>, int> previous_keys;  // BasisKey -> its column
  std::optional<DcbBasis> last_basis;
  DesignMatrix last_design;
  Eigen::MatrixX3d last_fallback;
  bool last_has_faces = true;
  auto record = [&](const Solution& s, RoundStatistics* rs) {
    rs->rmse_percent = s.rmse;
    rs->max_error_percent = s.max;
    model.control_points = s.control_points;
    result.errors_percent = s.errors;
    stats.final_result = *rs;
  };
  const double rounds_fraction = 0.7 / options.max_rounds;
  for (int round = 0; round < options.max_rounds; ++round) {
    const Stopwatch round_clock;
    const double base = 0.3 + rounds_fraction * round;
    const int new_knots = round == 0 && options.initial_knots > 0
                              ? options.initial_knots
                              : options.knots_per_round;
    // Knot placement with the existing knots fixed.
    report("knot placement", base);
    RoundDetails details;
    stage = Stopwatch();
    SDCB_ASSIGN_OR_RETURN(KnotPlacement placement,
                          PlaceKnots(density, knots, new_knots, cvt));
    details.timings.knot_placement = stage.Seconds();
    details.cvt_initial_energy = placement.initial_energy;
    details.cvt_final_energy = placement.final_energy;
    details.cvt_iterations = placement.iterations;
    details.min_knot_separation = placement.min_separation;
    // Configurations and basis.
    report("configurations", base + 0.25 * rounds_fraction);
    stage = Stopwatch();
    SDCB_ASSIGN_OR_RETURN(
        DelaunayConfigurations configurations,
        ComputeDelaunayConfigurations(placement.knots, options.degree));
    details.timings.configurations = stage.Seconds();
    if (round > 0 && static_cast<int>(configurations.sets.size()) >
                         options.max_control_points) {
      // The previous round's model is the result.
      if (!last_has_faces && nf > 0) {
        RoundDetails& last = result.round_details.back();
        SDCB_ASSIGN_OR_RETURN(const Solution s,
                              solve_with_faces(*last_basis, last_design,
                                               last_fallback, &last.timings));
        record(s, &stats.rounds.back());
        last.face_samples = true;
      }
      break;
    }
    report("basis", base + 0.4 * rounds_fraction);
    stage = Stopwatch();
    SDCB_ASSIGN_OR_RETURN(DcbBasis basis,
                          DcbBasis::Create(placement.knots, configurations));
    // Basis functions unchanged since the last round (same knots, same
    // boundary triples) keep their values: only new ones are evaluated.
    std::vector<int> previous_columns(basis.size(), -1);
    std::map<std::vector<int>, int> columns_by_key;
    for (int i = 0; i < basis.size(); ++i) {
      const std::vector<int> key = BasisKey(configurations.sets[i]);
      auto it = previous_keys.find(key);
      if (it != previous_keys.end()) {
        previous_columns[i] = it->second;
        ++details.reused_basis_functions;
      }
      columns_by_key.emplace(key, i);
    }
    DesignMatrix raw = BuildRawDesignMatrix(
        basis, u, round > 0 ? &previous_raw : nullptr, &previous_columns);
    DesignMatrix design = NormalizeRows(raw);
    details.timings.basis = stage.Seconds();
    // Least squares.
    report("solve", base + 0.7 * rounds_fraction);
    stage = Stopwatch();
    Eigen::MatrixX3d fallback =
        NearestSamplePrior(basis, parameter_tree, samples);
    SDCB_ASSIGN_OR_RETURN(Solution solution, solve(design, samples, fallback));
    details.timings.solve = stage.Seconds();
    const bool last_round = round + 1 == options.max_rounds;
    if (nf > 0 && (solution.rmse <= options.rmse_percent || last_round)) {
      SDCB_ASSIGN_OR_RETURN(solution, solve_with_faces(basis, design, fallback,
                                                       &details.timings));
      details.face_samples = true;
    }

    RoundStatistics rs;
    rs.round = round;
    rs.knots = static_cast<int>(placement.knots.rows());
    rs.control_points = basis.size();
    rs.seconds = round_clock.Seconds();
    record(solution, &rs);
    details.timings.total = rs.seconds;
    stats.rounds.push_back(rs);
    stats.final_result = rs;
    stats.timings.knot_placement += details.timings.knot_placement;
    stats.timings.configurations += details.timings.configurations;
    stats.timings.basis += details.timings.basis;
    stats.timings.solve += details.timings.solve;
    last_has_faces = details.face_samples || nf == 0;
    result.round_details.push_back(details);

    previous_raw = std::move(raw);
    previous_keys = std::move(columns_by_key);
    knots = placement.knots;
    model.knots = placement.knots;
    model.configurations = std::move(configurations);
    if (rs.rmse_percent <= options.rmse_percent && last_has_faces) {
      result.reached_target = true;
      break;
    }
    // Next round's density: the error, normalized, to the power alpha.
    if (solution.errors.maxCoeff() > 0) {
      SDCB_ASSIGN_OR_RETURN(density.values,
                            DensityFromValues(solution.errors, options.alpha));
    }
    last_basis.emplace(std::move(basis));
    last_design = std::move(design);
    last_fallback = std::move(fallback);
  }
  if (options.store_parameters) model.parameters = u;
  stats.timings.total = total.Seconds();
  result.statistics = stats;
  stats.timings = StageTimings();
  for (RoundStatistics& r : stats.rounds) r.seconds = 0;
  stats.final_result.seconds = 0;
  report("done", 1.0);
  return result;
}

}  // namespace sdcb
