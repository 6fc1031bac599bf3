#include "sdcb/core/fit/fit_options.h"

#include <cmath>
#include <string>

#include "sdcb/core/sphere/unit_vector_grid.h"

namespace sdcb {
namespace {

// The default Hausdorff target, in multiples of the rms target: on CGAL's
// meshes a fit that reaches its rms has a Hausdorff distance 2 to 9 times it
// and more at sharp feature lines (fandisk 15x, fandisk_large 16x;
// docs/FITTING.md).
constexpr double kDefaultMaxErrorRatio = 10.0;

}  // namespace

Status CheckFitOptions(const FitOptions& o) {
  if (o.degree < 2 || o.degree > kMaxSplineDegree) {
    return InvalidArgumentError("degree must be 2..5");
  }
  if (!(o.rmse_percent > 0) || !std::isfinite(o.rmse_percent)) {
    return InvalidArgumentError(
        "the RMSE target must be a positive percentage");
  }
  if (o.knots_per_round < 1 || o.initial_knots < 0 || o.max_rounds < 1 ||
      o.max_control_points < 1 || o.threads < 0 ||
      o.round_samples_per_knot < 1 || o.final_surface_samples < 1 ||
      o.max_fold_rounds < 0 || o.final_mesh_samples < 0 || o.map_vertices < 0 ||
      o.retry_map_vertices < 0) {
    return InvalidArgumentError(
        "knots per round, rounds, control points and sample counts must be "
        "positive (final mesh samples, map vertices >= 0), threads >= 0");
  }
  if (!std::isfinite(o.max_error_percent)) {
    return InvalidArgumentError("the max-error target must be finite");
  }
  if (!(o.knots_growth >= 0 && o.knots_growth <= 10)) {
    return InvalidArgumentError("the knot growth must be in [0, 10]");
  }
  for (double v :
       {o.alpha, o.regularization, o.lambda, o.samples_per_spacing}) {
    if (!(v > 0) || !std::isfinite(v)) {
      return InvalidArgumentError(
          "alpha, lambda, regularization and samples per spacing must be "
          "finite and > 0");
    }
  }
  if (!(o.thinned_cells_per_spacing >= 0) ||
      !std::isfinite(o.thinned_cells_per_spacing)) {
    return InvalidArgumentError(
        "the thinned cells per spacing must be finite and >= 0");
  }
  if (o.knot_grid_bits != 0 && (o.knot_grid_bits < kMinUnitVectorGridBits ||
                                o.knot_grid_bits > kMaxUnitVectorGridBits)) {
    return InvalidArgumentError("the knot grid needs 0 (off) or " +
                                std::to_string(kMinUnitVectorGridBits) + ".." +
                                std::to_string(kMaxUnitVectorGridBits) +
                                " bits");
  }
  if (!(o.fairness >= 0) || !std::isfinite(o.fairness)) {
    return InvalidArgumentError("the fairness weight must be finite and >= 0");
  }
  for (double factor : o.retry_lambda_factors) {
    if (!(factor > 0) || !std::isfinite(factor) || !(o.lambda * factor > 0)) {
      return InvalidArgumentError(
          "every retry lambda factor must be finite and > 0");
    }
  }
  if (o.basis_form != BasisForm::kNormalized &&
      o.basis_form != BasisForm::kRaw) {
    return InvalidArgumentError("unknown basis form");
  }
  return Status::Ok();
}

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
    case FitStage::kMeasure:
      return "measure";
    case FitStage::kDone:
      return "done";
  }
  return "?";
}

double MaxErrorTarget(const FitOptions& o) {
  return o.max_error_percent == 0 ? kDefaultMaxErrorRatio * o.rmse_percent
                                  : o.max_error_percent;
}

RecordedFitOptions RecordFitOptions(const FitOptions& o) {
  RecordedFitOptions r;
  r.degree = o.degree;
  r.rmse_percent = o.rmse_percent;
  r.max_error_percent = MaxErrorTarget(o);
  r.knots_per_round = o.knots_per_round;
  r.knots_growth = o.knots_growth;
  r.initial_knots = o.initial_knots;
  r.max_rounds = o.max_rounds;
  r.max_control_points = o.max_control_points;
  r.lambda = o.lambda;
  r.alpha = o.alpha;
  r.regularization = o.regularization;
  r.fairness = o.fairness;
  r.samples_per_spacing = o.samples_per_spacing;
  r.thinned_cells_per_spacing = o.thinned_cells_per_spacing;
  r.max_fold_rounds = o.max_fold_rounds;
  r.fallback_accepts_folds = o.fallback_accepts_folds;
  r.round_samples_per_knot = o.round_samples_per_knot;
  r.final_surface_samples = o.final_surface_samples;
  r.final_mesh_samples = o.final_mesh_samples;
  r.knot_grid_bits = o.knot_grid_bits;
  r.map_vertices = o.map_vertices;
  return r;
}

}  // namespace sdcb
