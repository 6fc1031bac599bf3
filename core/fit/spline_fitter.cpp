#include "sdcb/core/fit/spline_fitter.h"

#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sdcb/core/fit/feature_round.h"
#include "sdcb/core/fit/fit_mesh.h"
#include "sdcb/core/fit/fit_progress.h"
#include "sdcb/core/fit/fit_round.h"
#include "sdcb/core/fit/retry_strategy.h"
#include "sdcb/core/fit/stop_rule.h"
#include "sdcb/core/knots/feature_knots.h"
#include "sdcb/core/knots/spherical_cvt.h"
#include "sdcb/core/measure/surface_deviation.h"
#include "sdcb/core/mesh/curvature.h"
#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/param/spherical_parameterization.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {

// Everything a fit keeps between rounds.
struct SplineFitter::State {
  explicit State(FitOptions o)
      : options(std::move(o)),
        progress(options.progress),
        stop(options),
        fallback(options.fallback_accepts_folds) {}

  FitOptions options;
  // The fit's own arena: parallel work runs inside it, so the fit uses at
  // most options.threads threads without touching process-wide TBB limits.
  std::unique_ptr<tbb::task_arena> arena;
  Stopwatch clock;  // since Create
  ProgressReporter progress;
  FitMesh fit;
  // Round 0 on the feature corners' clusters, while it is to be tried.
  FeatureRound feature_round;
  SphericalDensity density;  // of the next round's knots
  StopRule stop;
  FitResult result;
  // The rounds kept to be returned if the target is missed.
  FallbackRounds fallback;
  // Whether the latest round's vertex errors are |F(u_i) - x_i| at every
  // vertex, not a thinned round's cell values.
  bool vertex_errors_exact = true;
  bool finished = false;
  bool paused = false;          // the latest AddRound held its round back
  int held_control_points = 0;  // that round's

  template <typename F>
  auto InArena(F&& f) {
    return arena->execute(std::forward<F>(f));
  }

  // Parameterizes the mesh on the sphere (Sec. 4.3) and, meanwhile, builds
  // the AABB tree of `measured` (the surface the errors are measured
  // against) and the curvedness of `map_mesh`, the round-0 density's.
  StatusOr<Eigen::VectorXd> Parameterize(const TriangleMesh& map_mesh,
                                         const TriangleMesh& measured);
  Status RunRound();
  // Adds the round of `placed` and `solved` to the model and the result.
  void RecordRound(int round, const Eigen::VectorXd& vertex_errors,
                   double seconds, PlacedRound* placed,
                   const SolvedRound& solved, RoundDetails* details);
  // Forgets a round 0 on the feature clusters that missed the target, as if
  // it had not run (its seconds stay in the stage timings); the next round
  // is FeatureRound::Drop's.
  void DropFeatureRound();
  // Ends the fit; a fit that missed its target returns its best round
  // (FallbackRounds::ReturnBest).
  Status Finish(bool reached, std::string shortfall);
  // The returned round measured as a reached one is (its final statistics
  // become the dense measurement's); reached when that meets the target.
  Status MeasureReturned();
};

StatusOr<Eigen::VectorXd> SplineFitter::State::Parameterize(
    const TriangleMesh& map_mesh, const TriangleMesh& measured) {
  progress.Report(FitStage::kParameterization, 0, 0);
  Stopwatch stage;
  SphericalParameterizationOptions param_options;
  param_options.lambda = options.lambda;
  param_options.threads = options.threads;
  param_options.progress = [this](const std::string&, double f) {
    progress.Report(FitStage::kParameterization, 0, f);
  };
  // Meanwhile, independent of it, the mesh's AABB tree and the curvedness
  // (step 2): they keep busy the threads the parameterization's sequential
  // parts leave idle. Same results; all three count as this stage.
  std::optional<StatusOr<MeshDistance>> distance;
  std::optional<StatusOr<Eigen::VectorXd>> curvedness;
  SDCB_ASSIGN_OR_RETURN(const SphericalParameterization param, InArena([&] {
                          tbb::task_group side;
                          side.run([&] {
                            distance = MeshDistance::Create(measured);
                            curvedness = Curvedness(map_mesh);
                          });
                          StatusOr<SphericalParameterization> p =
                              ParameterizeOnSphere(map_mesh, param_options);
                          side.wait();
                          return p;
                        }));
  fit.UseParameters(param.sphere);
  SDCB_RETURN_IF_ERROR(fit.UpdateRegion());
  SDCB_ASSIGN_OR_RETURN(fit.mesh_distance, std::move(*distance));
  result.timings.parameterization = stage.Seconds();
  return std::move(*curvedness);
}

StatusOr<SplineFitter> SplineFitter::Create(const TriangleMesh& mesh,
                                            FitOptions options) {
  return Create(mesh, nullptr, std::move(options));
}

StatusOr<SplineFitter> SplineFitter::Create(const FilledMesh& filled,
                                            FitOptions options) {
  if (filled.boundary_loops.empty()) return Create(filled.mesh, options);
  return Create(filled.Part(), &filled, std::move(options));
}

StatusOr<SplineFitter> SplineFitter::Create(const TriangleMesh& mesh,
                                            const FilledMesh* filled,
                                            FitOptions options) {
  SDCB_RETURN_IF_ERROR(CheckFitOptions(options));
  auto state = std::make_unique<State>(std::move(options));
  State& s = *state;
  const FitOptions& o = s.options;
  // (`automatic` is copied: binding a reference to it needs a definition
  // this TBB version does not export.)
  const int automatic = tbb::task_arena::automatic;
  s.arena =
      std::make_unique<tbb::task_arena>(o.threads > 0 ? o.threads : automatic);
  SDCB_RETURN_IF_ERROR(s.arena->execute(
      [&] { return RequireClosedGenusZero(filled ? filled->mesh : mesh); }));

  SplineModel& model = s.result.model;
  model.degree = o.degree;
  model.basis_form = o.basis_form;
  SDCB_ASSIGN_OR_RETURN(model.transform, ComputeNormalizingTransform(mesh));
  model.source.num_vertices = mesh.num_vertices();
  model.source.num_faces = mesh.num_faces();
  model.source.hash = HashTriangleMesh(mesh);
  SDCB_ASSIGN_OR_RETURN(s.result.features,
                        DetectFeatures(mesh, o.feature_angle_degrees));
  // The mesh the map and the fit use: the input, or the input split
  // (FitOptions::map_vertices), its first rows the input's vertices.
  // An open part is mapped and fitted with its holes filled; without
  // feature rounds or a split (the fill's faces follow the part's).
  const bool feature_curves = filled == nullptr && o.keep_features &&
                              FeatureCurvesJoinCorners(s.result.features);
  const std::optional<TriangleMesh> split =
      feature_curves || filled ? std::nullopt
                               : SplitForMap(mesh, o.map_vertices);
  const TriangleMesh& map_mesh =
      filled ? filled->mesh : (split ? *split : mesh);
  s.fit = filled ? NormalizedOpenFitMesh(*filled, model.transform)
                 : NormalizedFitMesh(map_mesh, model.transform,
                                     mesh.num_vertices());
  // An open part's fill is not a split of it: the map is of its vertices.
  s.result.map_vertices =
      filled ? mesh.num_vertices() : static_cast<int>(map_mesh.num_vertices());
  model.statistics.options = RecordFitOptions(o);
  model.statistics.error_measure = ErrorMeasure::kDenseTwoSided;

  // The measurements' AABB tree holds the input's own triangles when the map
  // uses its split: the same surface, with many times fewer triangles to
  // search.
  std::optional<TriangleMesh> unsplit;
  if (split) {
    unsplit.emplace();
    unsplit->vertices = s.fit.mesh.vertices.topRows(mesh.num_vertices());
    unsplit->faces = mesh.faces;
  }

  // 1. Spherical parameterization (Sec. 4.3).
  SDCB_ASSIGN_OR_RETURN(
      Eigen::VectorXd curvedness,
      s.Parameterize(map_mesh, unsplit ? *unsplit : s.fit.measured()));

  // 2. Round-0 density: curvedness^alpha (Sec. 4.4).
  const Stopwatch stage;
  if (!(curvedness.maxCoeff() > 0)) curvedness.setOnes();  // flat: uniform
  s.density = SphericalDensity{s.fit.u, s.fit.mesh.faces, Eigen::VectorXd()};
  SDCB_ASSIGN_OR_RETURN(s.density.values,
                        DensityFromValues(curvedness, o.alpha));
  // Round 0 tries the corners' knot clusters alone first (RunRound) when
  // they can keep every feature (core/fit/feature_round.h).
  if (feature_curves) s.feature_round.Plan(s.result.features, &s.fit);
  s.result.timings.knot_placement += stage.Seconds();
  return SplineFitter(std::move(state));
}

SplineFitter::SplineFitter(std::unique_ptr<State> state)
    : state_(std::move(state)) {}
SplineFitter::SplineFitter(SplineFitter&&) noexcept = default;
SplineFitter& SplineFitter::operator=(SplineFitter&&) noexcept = default;
SplineFitter::~SplineFitter() = default;

bool SplineFitter::finished() const { return !state_ || state_->finished; }

void SplineFitter::PauseAbove(int control_points) {
  if (!state_) return;
  state_->stop.set_pause_above(control_points);
  state_->paused = false;
}

bool SplineFitter::paused() const { return state_ && state_->paused; }

int SplineFitter::held_control_points() const {
  return paused() ? state_->held_control_points : 0;
}

bool SplineFitter::taken() const { return !state_; }

bool SplineFitter::reached_target() const {
  return state_ && state_->result.model.statistics.reached_target;
}

void SplineFitter::SetMaxControlPoints(int control_points) {
  if (!state_) return;
  State& s = *state_;
  s.options.max_control_points = control_points;
  s.stop.set_max_control_points(control_points);
  s.result.model.statistics.options = RecordFitOptions(s.options);
}

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
  if (paused()) {
    return InvalidArgumentError("the fit is paused; PauseAbove(0) resumes it");
  }
  return state_->InArena([&] {
    // The round on the feature clusters is an attempt: when it cannot be
    // built (a basis with a hole, too many samples) the fit goes on from
    // its usual round 0, as when it misses the target.
    const bool feature_round = state_->feature_round.pending();
    Status status = state_->RunRound();
    if (!status.ok() && feature_round) {
      state_->DropFeatureRound();
      return Status::Ok();
    }
    return status;
  });
}

Status SplineFitter::State::RunRound() {
  SplineModel& model = result.model;
  const std::vector<RoundStatistics>& rounds = model.statistics.rounds;
  const int round = static_cast<int>(rounds.size());
  const Stopwatch round_clock;
  RoundDetails details;
  const RoundContext context{options, fit,      result.features,
                             stop,    progress, round};
  const bool on_features = round == 0 && feature_round.pending();

  // 1.-3. Knots, configurations, the least-squares problem. No room for
  // the round's knots, or too many control points: the rounds so far are
  // the result.
  SDCB_ASSIGN_OR_RETURN(
      PlacedRound placed,
      PlaceRound(context, density, model.knots,
                 stop.RoundKnots(rounds, static_cast<int>(model.knots.rows())),
                 on_features ? &feature_round.knots() : nullptr, &details));
  if (placed.paused) {
    paused = true;  // placed again, the same way, when resumed
    held_control_points = placed.held_control_points;
    return Status::Ok();
  }
  if (!placed.problem) return Finish(false, std::move(placed.shortfall));
  RoundProblem& problem = *placed.problem;
  // 4. Least squares; 5. measure.
  SDCB_ASSIGN_OR_RETURN(const SolvedRound solved,
                        SolveAndMeasure(context, &problem, &details));
  const Eigen::VectorXd vertex_errors = RoundVertexErrors(
      fit, problem.samples, solved.fitted, solved.vertex_points);
  RecordRound(round, vertex_errors, round_clock.Seconds(), &placed, solved,
              &details);

  // 6. Stop, or go on.
  if (solved.reached) {
    result.features_kept = on_features;
    return Finish(true, "");
  }
  if (on_features) {
    // The clusters alone did not meet the target (features that are not
    // between corners, curved ones, or a shape that needs more knots): the
    // fit starts again from its usual round 0, which does not keep them.
    DropFeatureRound();
    return Status::Ok();
  }
  int estimated_rounds = progress.estimated_rounds();
  std::optional<std::string> shortfall =
      stop.AfterMissedRound(rounds, &estimated_rounds);
  progress.set_estimated_rounds(estimated_rounds);
  if (shortfall) return Finish(false, std::move(*shortfall));
  NextDensity(options, problem, solved.fitted, vertex_errors, solved.deviation,
              stop.fold_round(), &fit, &density);
  return Status::Ok();
}

void SplineFitter::State::RecordRound(int round,
                                      const Eigen::VectorXd& vertex_errors,
                                      double seconds, PlacedRound* placed,
                                      const SolvedRound& solved,
                                      RoundDetails* details) {
  // The round's statistics; the vertex errors are the paper's measure,
  // |F(u_i) - x_i|, where F(u_i) is known; a round of thinned samples that
  // was not measured densely gives each vertex its cell's kept row's.
  SplineModel& model = result.model;
  FitStatistics& stats = model.statistics;
  const Eigen::Index input_vertices = fit.input_vertices;
  RoundStatistics rs;
  rs.round = round;
  rs.knots = static_cast<int>(placed->placement.knots.rows());
  rs.control_points = static_cast<int>(solved.control_points.rows());
  rs.rmse_percent = solved.deviation.rms_percent;
  rs.max_error_percent = solved.deviation.hausdorff_percent;
  // The statistics at the input's vertices (a split mesh's first rows).
  const Eigen::VectorXd input_errors = vertex_errors.head(input_vertices);
  rs.vertex_rmse_percent = std::sqrt(input_errors.squaredNorm() /
                                     std::max<Eigen::Index>(input_vertices, 1));
  rs.vertex_max_error_percent =
      input_vertices > 0 ? input_errors.maxCoeff() : 0;
  rs.folded_area_percent = solved.deviation.folded_area_percent;
  rs.boundary_error_percent = solved.deviation.boundary_percent;
  model.knots = placed->placement.knots;
  model.configurations = std::move(placed->configurations);
  model.control_points = solved.control_points;
  result.vertex_errors_percent = input_errors;
  vertex_errors_exact = solved.vertex_points.rows() == fit.mesh.vertices.rows();
  stats.rounds.push_back(rs);
  stats.final_result = rs;
  details->timings.total = seconds;
  AddRoundStages(details->timings, &result.timings);
  result.round_details.push_back(*details);
  fallback.Offer(model, input_errors, vertex_errors_exact);
}

void SplineFitter::State::DropFeatureRound() {
  feature_round.Drop(result.features, options.degree, &fit);
  SplineModel& model = result.model;
  model.knots.resize(0, 3);
  model.configurations = DelaunayConfigurations();
  model.control_points.resize(0, 3);
  model.statistics.rounds.clear();
  model.statistics.final_result = RoundStatistics();
  result.round_details.clear();
  fallback.Clear();
  vertex_errors_exact = true;
}

Status SplineFitter::State::Finish(bool reached, std::string shortfall) {
  finished = true;
  result.model.statistics.reached_target = reached;
  if (reached) return Status::Ok();
  result.shortfall = std::move(shortfall);
  return fallback.ReturnBest({&result, &vertex_errors_exact},
                             [this] { return MeasureReturned(); });
}

Status SplineFitter::State::MeasureReturned() {
  RoundStatistics& kept = result.model.statistics.final_result;
  const Stopwatch clock;
  SDCB_ASSIGN_OR_RETURN(const SphericalSpline surface,
                        SurfaceFromModel(result.model));
  // A thinned round's vertex errors were its cells': F(u_i) at every
  // vertex now, for the paper's measure and as candidates.
  Eigen::MatrixX3d vertex_points;
  if (!vertex_errors_exact) {
    vertex_points = surface.EvaluateMany(fit.u);
    result.vertex_errors_percent = 100.0 * (vertex_points - fit.mesh.vertices)
                                               .topRows(fit.input_vertices)
                                               .rowwise()
                                               .norm();
    const Eigen::VectorXd& e = result.vertex_errors_percent;
    kept.vertex_rmse_percent =
        std::sqrt(e.squaredNorm() / std::max<Eigen::Index>(e.size(), 1));
    kept.vertex_max_error_percent = e.size() > 0 ? e.maxCoeff() : 0;
    vertex_errors_exact = true;
  }
  SDCB_ASSIGN_OR_RETURN(
      const SurfaceDeviation dense,
      MeasureFitSurface(options, fit, surface,
                        vertex_points.rows() > 0 ? &vertex_points : nullptr,
                        true));
  result.timings.measure += clock.Seconds();
  kept.rmse_percent = dense.rms_percent;
  kept.max_error_percent = dense.hausdorff_percent;
  kept.folded_area_percent = dense.folded_area_percent;
  kept.boundary_error_percent = dense.boundary_percent;
  // The rounds' mesh -> surface bound (the parametric residual) can keep a
  // round from the final measurement that it would pass (the 8-vertex
  // beam: its rounds said 0.31 % rms, densely it is 0.022 %). Measured as
  // a reached round is, it has reached.
  if (CompareWithTarget(stop.target(), kept).reached()) {
    result.model.statistics.reached_target = true;
    result.shortfall.clear();
  }
  return Status::Ok();
}

FitResult SplineFitter::TakeResult() {
  State& s = *state_;
  if (s.options.store_parameters) {
    s.result.model.parameters = s.fit.u.topRows(s.fit.input_vertices);
  }
  s.result.trims = s.fit.Trims();
  s.result.timings.total = s.clock.Seconds();
  s.progress.Report(FitStage::kDone, rounds(), 0);
  FitResult out = std::move(s.result);
  state_.reset();
  return out;
}

namespace {

template <typename Input>
StatusOr<FitResult> RunFit(const Input& input, const FitOptions& options) {
  SDCB_ASSIGN_OR_RETURN(SplineFitter fitter,
                        SplineFitter::Create(input, options));
  while (!fitter.finished()) SDCB_RETURN_IF_ERROR(fitter.AddRound());
  return fitter.TakeResult();
}

// Adds rounds until `fitter` is finished or paused.
Status RunUntilPaused(SplineFitter* fitter) {
  while (!fitter->finished() && !fitter->paused()) {
    SDCB_RETURN_IF_ERROR(fitter->AddRound());
  }
  return Status::Ok();
}

// The fits of an input with fewer vertices than `first` (paused after its
// round 0) has control points in any round: FitAgain would fit it again
// split whenever it reached, and keep the fit that reaches with fewer
// control points (the first on a tie). The two take turns, each running
// its rounds up to the other's next one (the first on a tie), until one
// finishes: the first to reach is the fit FitAgain keeps. A fit that
// finishes missing leaves the other to run to the end, and a split fit
// that reaches is returned (where FitAgain might have kept a first fit
// that missed); both missing, FitAgain decides as without the turns.
StatusOr<FitResult> FitInTurns(const TriangleMesh& mesh,
                               const FitOptions& options, const FitRunner& run,
                               SplineFitter first) {
  const std::optional<FitOptions> split_options =
      SplitFitOptions(mesh, options, options.max_control_points);
  StatusOr<SplineFitter> split =
      split_options ? SplineFitter::Create(mesh, *split_options)
                    : StatusOr<SplineFitter>(InternalError("no split fit"));
  if (split.ok()) {
    split->PauseAbove(1);  // round 0, then the next one held
    SDCB_RETURN_IF_ERROR(RunUntilPaused(&*split));
    while (!first.finished() && !split->finished()) {
      if (first.held_control_points() <= split->held_control_points()) {
        first.PauseAbove(split->held_control_points());
        SDCB_RETURN_IF_ERROR(RunUntilPaused(&first));
      } else {
        split->PauseAbove(std::max(1, first.held_control_points() - 1));
        SDCB_RETURN_IF_ERROR(RunUntilPaused(&*split));
      }
    }
    // The one that finished missing: the other runs to the end.
    SplineFitter& rest = first.finished() ? *split : first;
    if (!(first.finished() ? first : *split).reached_target()) {
      rest.PauseAbove(0);
      SDCB_RETURN_IF_ERROR(RunUntilPaused(&rest));
    }
    const bool split_reached = split->finished() && split->reached_target();
    if ((first.finished() && first.reached_target()) || split_reached) {
      const bool take_split = !(first.finished() && first.reached_target());
      FitResult other = take_split ? first.TakeResult() : split->TakeResult();
      FitResult kept = take_split ? split->TakeResult() : first.TakeResult();
      kept.split_retry_run = true;
      kept.split_retry_returned = take_split;
      AddSeconds(other, &kept);
      return kept;
    }
  } else {
    first.PauseAbove(0);
    SDCB_RETURN_IF_ERROR(RunUntilPaused(&first));
  }
  // Both missed (or no split fit): FitAgain, given the split fit when its
  // cap is the one it asks for.
  const FitRunner again = [&](const FitOptions& o) -> StatusOr<FitResult> {
    if (!split.ok()) return split.status();
    if (o.max_control_points != split_options->max_control_points) {
      return run(o);
    }
    return split->TakeResult();
  };
  FitResult best = FitAgain(mesh, options, first.TakeResult(), run, &again);
  if (split.ok() && !split->taken()) AddSeconds(split->TakeResult(), &best);
  return best;
}

}  // namespace

StatusOr<FitResult> FitSphericalSpline(const TriangleMesh& mesh,
                                       const FitOptions& options) {
  const FitRunner run = [&mesh](const FitOptions& o) {
    return RunFit(mesh, o);
  };
  if (RunsNoFurtherFits(mesh, options)) return run(options);
  // FitAgain fits a first fit that needs more control points than the input
  // has vertices again on the split input. That split fit starts as soon as
  // the first would pass that many, and runs as far: when it reaches the
  // target there, it is what FitAgain returns, and the first fit stops.
  // (Had the first fit gone on to miss with folds on an input that passes
  // through itself, FitAgain would not have split; a split fit that reaches
  // is returned.) Otherwise the first fit goes on, and FitAgain follows with
  // the split fit continued where it paused: the same fits as without the
  // pauses.
  const int vertices = static_cast<int>(mesh.num_vertices());
  SDCB_ASSIGN_OR_RETURN(SplineFitter first,
                        SplineFitter::Create(mesh, options));
  first.PauseAbove(vertices);
  SDCB_RETURN_IF_ERROR(RunUntilPaused(&first));
  if (first.paused() && first.rounds() == 1 &&
      first.model().statistics.rounds[0].control_points > vertices) {
    return FitInTurns(mesh, options, run, std::move(first));
  }
  std::optional<StatusOr<SplineFitter>> split;
  if (first.paused()) {
    if (const std::optional<FitOptions> split_options =
            SplitFitOptions(mesh, options, options.max_control_points)) {
      split = SplineFitter::Create(mesh, *split_options);
      if (split->ok()) {
        (*split)->PauseAbove(vertices);
        const Status ran = RunUntilPaused(&**split);
        if (!ran.ok()) split = ran;
      }
    }
    if (split && split->ok() && (*split)->finished() &&
        (*split)->reached_target()) {
      FitResult early = (*split)->TakeResult();
      early.split_retry_run = true;
      early.split_retry_returned = true;
      AddSeconds(first.TakeResult(), &early);
      return early;
    }
    first.PauseAbove(0);
    SDCB_RETURN_IF_ERROR(RunUntilPaused(&first));
  }
  if (!split) return FitAgain(mesh, options, first.TakeResult(), run);
  // The split fit FitAgain asks for, with its control-point cap: the one
  // started above, continued; started again when its rounds already passed
  // that cap (a first fit that missed returns a round of fewer control
  // points than the input has vertices).
  const FitRunner continue_split =
      [&split, &run](const FitOptions& o) -> StatusOr<FitResult> {
    if (!split->ok()) return split->status();
    SplineFitter& fitter = **split;
    if (fitter.rounds() > 1 &&
        fitter.model().statistics.final_result.control_points >
            o.max_control_points) {
      return run(o);
    }
    fitter.SetMaxControlPoints(o.max_control_points);
    fitter.PauseAbove(0);
    SDCB_RETURN_IF_ERROR(RunUntilPaused(&fitter));
    return fitter.TakeResult();
  };
  FitResult best =
      FitAgain(mesh, options, first.TakeResult(), run, &continue_split);
  // A split fit FitAgain did not ask for still took its seconds.
  if (split->ok() && !(*split)->taken()) {
    AddSeconds((*split)->TakeResult(), &best);
  }
  return best;
}

StatusOr<FitResult> FitSphericalSpline(const FilledMesh& filled,
                                       const FitOptions& options) {
  if (filled.boundary_loops.empty()) {
    return FitSphericalSpline(filled.mesh, options);
  }
  const FitRunner run = [&filled](const FitOptions& o) {
    return RunFit(filled, o);
  };
  SDCB_ASSIGN_OR_RETURN(FitResult first, run(options));
  if (options.map_vertices > 0 || options.retry_map_vertices == 0) {
    return first;  // one fit asked for
  }
  // A thin part's fits with a smaller lambda; never split (the fill's faces
  // follow the part's own).
  FitOptions again = options;
  again.retry_map_vertices = 0;
  return FitAgain(filled.Part(), again, std::move(first), run);
}

}  // namespace sdcb
