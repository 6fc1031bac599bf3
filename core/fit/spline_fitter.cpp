#include "sdcb/core/fit/spline_fitter.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <utility>

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

// Progress model (FitProgress::fraction). The parameterization takes about
// this share of a typical fit (bunny00: 1.9 s of 4.4 s; smaller meshes less).
constexpr double kParameterizationShare = 0.3;
// Where each stage starts within a round, as a share of the round's time
// (bunny00, degree 4: knot placement ~0.1 s, configurations ~0.01 s, basis
// ~0.2 s, solve ~0.1 s).
constexpr double kRoundStageStart[] = {
    0.0,   // knot placement
    0.25,  // configurations
    0.3,   // basis
    0.7,   // solve
};
// Rounds assumed before two rounds show the error's decay.
constexpr int kInitialRoundGuess = 5;

Status CheckOptions(const FitOptions& o) {
  if (o.degree < 2 || o.degree > kMaxSplineDegree) {
    return InvalidArgumentError("degree must be 2..5");
  }
  if (!(o.rmse_percent > 0) || !std::isfinite(o.rmse_percent)) {
    return InvalidArgumentError(
        "the RMSE target must be a positive percentage");
  }
  if (o.knots_per_round < 1 || o.initial_knots < 0 || o.max_rounds < 1 ||
      o.max_control_points < 1 || o.threads < 0) {
    return InvalidArgumentError(
        "knots per round, rounds and control points must be positive, "
        "threads >= 0");
  }
  for (double v : {o.alpha, o.regularization, o.lambda, o.face_weight}) {
    if (!(v > 0) || !std::isfinite(v)) {
      return InvalidArgumentError(
          "alpha, lambda, regularization and face weight must be finite and "
          "> 0");
    }
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

// Control points and the errors at the vertices, in percent of the largest
// side (normalized frame: side 1).
struct Solution {
  Eigen::MatrixX3d control_points;
  Eigen::VectorXd errors;
  double rmse = 0, max = 0;
};

}  // namespace

const char* FitStageName(FitStage stage) {
  switch (stage) {
    case FitStage::kParameterization:
      return "parameterization";
    case FitStage::kKnotPlacement:
      return "knot placement";
    case FitStage::kConfigurations:
      return "configurations";
    case FitStage::kBasis:
      return "basis";
    case FitStage::kSolve:
      return "solve";
    case FitStage::kDone:
      return "done";
  }
  return "?";
}

RecordedFitOptions RecordFitOptions(const FitOptions& o) {
  RecordedFitOptions r;
  r.degree = o.degree;
  r.rmse_percent = o.rmse_percent;
  r.knots_per_round = o.knots_per_round;
  r.initial_knots = o.initial_knots;
  r.max_rounds = o.max_rounds;
  r.max_control_points = o.max_control_points;
  r.lambda = o.lambda;
  r.alpha = o.alpha;
  r.regularization = o.regularization;
  r.face_samples = o.face_samples;
  r.face_weight = o.face_weight;
  return r;
}

// Everything a fit keeps between rounds.
struct SplineFitter::State {
  FitOptions options;
  // The fit's own arena: parallel work runs inside it, so the fit uses at
  // most options.threads threads without touching process-wide TBB limits.
  std::unique_ptr<tbb::task_arena> arena;
  Stopwatch clock;  // since Create

  Eigen::MatrixX3i faces;
  Eigen::MatrixX3d samples;  // the vertices in the normalized frame
  Eigen::MatrixX3d u;        // their sphere parameters
  // Centroid rows (FitOptions::face_samples): each triangle's parameter is
  // the normalized sum of its corners' sphere points; targets are the
  // vertices, then sqrt(face_weight) times each flat triangle's centroid.
  Eigen::MatrixX3d face_points;
  Eigen::MatrixX3d all_targets;
  std::unique_ptr<PointKdTree> parameter_tree;
  SphericalDensity density;  // of the next round's knots

  // The latest round, kept for the next one (reuse of basis values) and for
  // a final refit with the centroid rows.
  struct Round {
    DcbBasis basis;
    DesignMatrix raw;     // raw (eq. 4) values at the vertices
    DesignMatrix design;  // normalized rows
    Eigen::MatrixX3d fallback;
    std::map<std::vector<int>, int> columns_by_key;  // BasisKey -> column
    bool has_faces = false;
  };
  std::optional<Round> last;

  FitResult result;
  bool finished = false;
  int estimated_rounds = kInitialRoundGuess;

  template <typename F>
  auto InArena(F&& f) {
    return arena->execute(std::forward<F>(f));
  }

  // `within`: the finished share of the stage (parameterization) or of the
  // round (round stages).
  void Report(FitStage stage, int round, double within) {
    if (!options.progress) return;
    FitProgress p;
    p.stage = stage;
    p.round = round;
    if (stage == FitStage::kParameterization) {
      p.fraction = kParameterizationShare * within;
    } else if (stage == FitStage::kDone) {
      p.fraction = 1.0;
    } else {
      const double rounds = std::max(estimated_rounds, round + 1);
      p.fraction = kParameterizationShare +
                   (1.0 - kParameterizationShare) * (round + within) / rounds;
    }
    p.fraction = std::clamp(p.fraction, 0.0, 1.0);
    options.progress(p);
  }

  // Least squares for `design` (vertex rows first) and `targets`.
  StatusOr<Solution> Solve(const DesignMatrix& design,
                           const Eigen::MatrixX3d& targets,
                           const Eigen::MatrixX3d& fallback) const {
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
  }

  // The fit of `round` with the triangle-centroid rows added; adds its
  // seconds to `timings`.
  StatusOr<Solution> SolveWithFaces(const Round& round,
                                    StageTimings* timings) const {
    Stopwatch clock;
    const double root_weight = std::sqrt(options.face_weight);
    const DesignMatrix design = StackRows(
        round.design, root_weight * NormalizeRows(BuildRawDesignMatrix(
                                        round.basis, face_points)));
    timings->basis += clock.Seconds();
    clock = Stopwatch();
    StatusOr<Solution> s = Solve(design, all_targets, round.fallback);
    timings->solve += clock.Seconds();
    return s;
  }

  // Makes `s` the model's solution, recorded in the round statistics `rs`.
  void Record(const Solution& s, RoundStatistics* rs) {
    rs->rmse_percent = rs->vertex_rmse_percent = s.rmse;
    rs->max_error_percent = rs->vertex_max_error_percent = s.max;
    result.model.control_points = s.control_points;
    result.vertex_errors_percent = s.errors;
    result.model.statistics.final_result = *rs;
  }

  // Refits the latest round with the centroid rows unless it has them.
  Status FinalizeLastRound() {
    if (!last || last->has_faces) return Status::Ok();
    RoundDetails& details = result.round_details.back();
    SDCB_ASSIGN_OR_RETURN(const Solution s,
                          SolveWithFaces(*last, &details.timings));
    details.face_samples = true;
    last->has_faces = true;
    Record(s, &result.model.statistics.rounds.back());
    return Status::Ok();
  }

  Status RunRound();
};

StatusOr<SplineFitter> SplineFitter::Create(const TriangleMesh& mesh,
                                            FitOptions options) {
  SDCB_RETURN_IF_ERROR(CheckOptions(options));
  SDCB_RETURN_IF_ERROR(RequireClosedGenusZero(mesh));
  auto state = std::make_unique<State>();
  State& s = *state;
  s.options = std::move(options);
  const FitOptions& o = s.options;
  // (`automatic` is copied: binding a reference to it needs a definition
  // this TBB version does not export.)
  const int automatic = tbb::task_arena::automatic;
  s.arena =
      std::make_unique<tbb::task_arena>(o.threads > 0 ? o.threads : automatic);
  s.faces = mesh.faces;

  SplineModel& model = s.result.model;
  model.degree = o.degree;
  SDCB_ASSIGN_OR_RETURN(model.transform, ComputeNormalizingTransform(mesh));
  s.samples = model.transform.ToNormalized(mesh.vertices);
  model.source.num_vertices = mesh.num_vertices();
  model.source.num_faces = mesh.num_faces();
  model.source.hash = HashTriangleMesh(mesh);
  model.statistics.options = RecordFitOptions(o);
  model.statistics.error_measure = ErrorMeasure::kVertices;

  // 1. Spherical parameterization (Sec. 4.3).
  s.Report(FitStage::kParameterization, 0, 0);
  Stopwatch stage;
  SphericalParameterizationOptions param_options;
  param_options.lambda = o.lambda;
  param_options.threads = o.threads;
  param_options.progress = [&s](const std::string&, double f) {
    s.Report(FitStage::kParameterization, 0, f);
  };
  SDCB_ASSIGN_OR_RETURN(const SphericalParameterization param, s.InArena([&] {
    return ParameterizeOnSphere(mesh, param_options);
  }));
  s.u = param.sphere;
  s.result.timings.parameterization = stage.Seconds();

  const Eigen::Index nv = mesh.num_vertices();
  const Eigen::Index nf = o.face_samples ? mesh.num_faces() : 0;
  s.face_points.resize(nf, 3);
  s.all_targets.resize(nv + nf, 3);
  s.all_targets.topRows(nv) = s.samples;
  for (Eigen::Index f = 0; f < nf; ++f) {
    Eigen::RowVector3d p = Eigen::RowVector3d::Zero(), x = p;
    for (int k = 0; k < 3; ++k) {
      p += s.u.row(mesh.faces(f, k));
      x += s.samples.row(mesh.faces(f, k));
    }
    s.face_points.row(f) = p.normalized();
    s.all_targets.row(nv + f) = std::sqrt(o.face_weight) * x / 3.0;
  }
  s.parameter_tree = std::make_unique<PointKdTree>(s.u);

  // 2. Round-0 density: curvedness^alpha (Sec. 4.4).
  stage = Stopwatch();
  SDCB_ASSIGN_OR_RETURN(Eigen::VectorXd curvedness,
                        s.InArena([&] { return Curvedness(mesh); }));
  if (!(curvedness.maxCoeff() > 0)) curvedness.setOnes();  // flat: uniform
  s.density = SphericalDensity{s.u, mesh.faces, Eigen::VectorXd()};
  SDCB_ASSIGN_OR_RETURN(s.density.values,
                        DensityFromValues(curvedness, o.alpha));
  s.result.timings.knot_placement += stage.Seconds();
  return SplineFitter(std::move(state));
}

SplineFitter::SplineFitter(std::unique_ptr<State> state)
    : state_(std::move(state)) {}
SplineFitter::SplineFitter(SplineFitter&&) noexcept = default;
SplineFitter& SplineFitter::operator=(SplineFitter&&) noexcept = default;
SplineFitter::~SplineFitter() = default;

bool SplineFitter::finished() const { return !state_ || state_->finished; }

int SplineFitter::rounds() const {
  return state_
             ? static_cast<int>(state_->result.model.statistics.rounds.size())
             : 0;
}

const SplineModel& SplineFitter::model() const { return state_->result.model; }

Status SplineFitter::AddRound() {
  if (finished()) {
    return InvalidArgumentError("the fit is finished; no round can be added");
  }
  return state_->InArena([&] { return state_->RunRound(); });
}

Status SplineFitter::State::RunRound() {
  const FitOptions& o = options;
  SplineModel& model = result.model;
  FitStatistics& stats = model.statistics;
  const int round = static_cast<int>(stats.rounds.size());
  const Stopwatch round_clock;
  const int new_knots =
      round == 0 && o.initial_knots > 0 ? o.initial_knots : o.knots_per_round;
  // Knot placement with the existing knots fixed.
  Report(FitStage::kKnotPlacement, round, kRoundStageStart[0]);
  RoundDetails details;
  Stopwatch stage;
  SDCB_ASSIGN_OR_RETURN(
      KnotPlacement placement,
      PlaceKnots(density, model.knots, new_knots, CvtOptions()));
  details.timings.knot_placement = stage.Seconds();
  details.cvt_initial_energy = placement.initial_energy;
  details.cvt_final_energy = placement.final_energy;
  details.cvt_iterations = placement.iterations;
  details.min_knot_separation = placement.min_separation;

  // Configurations; a round that would exceed the control-point cap is not
  // added: the previous round's model is the result.
  Report(FitStage::kConfigurations, round, kRoundStageStart[1]);
  stage = Stopwatch();
  SDCB_ASSIGN_OR_RETURN(
      DelaunayConfigurations configurations,
      ComputeDelaunayConfigurations(placement.knots, o.degree));
  details.timings.configurations = stage.Seconds();
  if (round > 0 &&
      static_cast<int>(configurations.sets.size()) > o.max_control_points) {
    finished = true;
    return FinalizeLastRound();
  }

  // Basis. Basis functions unchanged since the last round (same knots, same
  // boundary triples) keep their values: only new ones are evaluated.
  Report(FitStage::kBasis, round, kRoundStageStart[2]);
  stage = Stopwatch();
  SDCB_ASSIGN_OR_RETURN(DcbBasis basis,
                        DcbBasis::Create(placement.knots, configurations));
  std::vector<int> previous_columns(basis.size(), -1);
  std::map<std::vector<int>, int> columns_by_key;
  for (int i = 0; i < basis.size(); ++i) {
    std::vector<int> key = BasisKey(configurations.sets[i]);
    if (last) {
      const auto it = last->columns_by_key.find(key);
      if (it != last->columns_by_key.end()) {
        previous_columns[i] = it->second;
        ++details.reused_basis_functions;
      }
    }
    columns_by_key.emplace(std::move(key), i);
  }
  DesignMatrix raw = BuildRawDesignMatrix(basis, u, last ? &last->raw : nullptr,
                                          &previous_columns);
  DesignMatrix design = NormalizeRows(raw);
  details.timings.basis = stage.Seconds();

  // Least squares on the vertices.
  Report(FitStage::kSolve, round, kRoundStageStart[3]);
  stage = Stopwatch();
  Eigen::MatrixX3d fallback =
      NearestSamplePrior(basis, *parameter_tree, samples);
  SDCB_ASSIGN_OR_RETURN(Solution solution, Solve(design, samples, fallback));
  details.timings.solve = stage.Seconds();

  last.emplace(Round{std::move(basis), std::move(raw), std::move(design),
                     std::move(fallback), std::move(columns_by_key),
                     face_points.rows() == 0});
  // A round whose vertex fit reaches the target, and the last round, are
  // refitted with the centroid rows.
  const bool last_allowed = round + 1 == o.max_rounds;
  if (!last->has_faces && (solution.rmse <= o.rmse_percent || last_allowed)) {
    SDCB_ASSIGN_OR_RETURN(solution, SolveWithFaces(*last, &details.timings));
    details.face_samples = true;
    last->has_faces = true;
  }

  RoundStatistics rs;
  rs.round = round;
  rs.knots = static_cast<int>(placement.knots.rows());
  rs.control_points = last->basis.size();
  Record(solution, &rs);
  details.timings.total = round_clock.Seconds();
  stats.rounds.push_back(rs);
  StageTimings& t = result.timings;
  t.knot_placement += details.timings.knot_placement;
  t.configurations += details.timings.configurations;
  t.basis += details.timings.basis;
  t.solve += details.timings.solve;
  result.round_details.push_back(details);
  model.knots = std::move(placement.knots);
  model.configurations = std::move(configurations);

  if (rs.rmse_percent <= o.rmse_percent && last->has_faces) {
    stats.reached_target = true;
    finished = true;
    return Status::Ok();
  }
  if (last_allowed) {
    finished = true;
    return Status::Ok();
  }
  // The number of rounds, estimated from the decay of the vertex RMSE.
  if (stats.rounds.size() >= 2) {
    const double previous = stats.rounds[stats.rounds.size() - 2].rmse_percent;
    const double decay = rs.rmse_percent / previous;
    if (decay > 0 && decay < 1) {
      const double more = std::ceil(std::log(o.rmse_percent / rs.rmse_percent) /
                                    std::log(decay));
      estimated_rounds = std::min<int>(
          o.max_rounds, round + 1 + static_cast<int>(std::max(1.0, more)));
    }
  }
  // Next round's density: the error, normalized, to the power alpha.
  if (solution.errors.maxCoeff() > 0) {
    SDCB_ASSIGN_OR_RETURN(density.values,
                          DensityFromValues(solution.errors, o.alpha));
  }
  return Status::Ok();
}

FitResult SplineFitter::TakeResult() {
  State& s = *state_;
  if (s.options.store_parameters) s.result.model.parameters = s.u;
  s.result.timings.total = s.clock.Seconds();
  s.Report(FitStage::kDone, rounds(), 0);
  FitResult out = std::move(s.result);
  state_.reset();
  return out;
}

StatusOr<FitResult> FitSphericalSpline(const TriangleMesh& mesh,
                                       const FitOptions& options) {
  SDCB_ASSIGN_OR_RETURN(SplineFitter fitter,
                        SplineFitter::Create(mesh, options));
  while (!fitter.finished()) SDCB_RETURN_IF_ERROR(fitter.AddRound());
  return fitter.TakeResult();
}

}  // namespace sdcb
