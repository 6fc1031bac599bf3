// What a fit returns (FitResult): the model, the seconds per stage, what
// each round did beyond the model's statistics (RoundDetails), the vertex
// errors, and why the target was missed.
#ifndef SDCB_CORE_FIT_FIT_RESULT_H_
#define SDCB_CORE_FIT_FIT_RESULT_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "sdcb/core/mesh/feature_curves.h"
#include "sdcb/core/sphere/trim_region.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

// Wall time per pipeline stage, in seconds.
struct StageTimings {
  // The parameterization, and the mesh's AABB tree and curvedness (round
  // 0's density), which run beside it.
  double parameterization = 0.0;
  double knot_placement = 0.0;
  double configurations = 0.0;
  double basis = 0.0;    // basis, design matrix and bending rows
  double solve = 0.0;    // least squares (all solves of the round)
  double measure = 0.0;  // error measurement, and the repair of small folds
  double total = 0.0;
};

// What one round did, beyond the model's RoundStatistics.
struct RoundDetails {
  StageTimings timings;  // this round's seconds per stage (no parameterization)
  double cvt_initial_energy = 0;  // CVT energy of the round's knot placement
  double cvt_final_energy = 0;
  int cvt_iterations = 0;
  // Times the round's knots were placed again with the density floored,
  // the basis on the knots placed before having a hole (I = 0 somewhere,
  // or at a knot outside every support; 0, 1 or 2).
  int hole_retries = 0;
  double min_knot_separation = 0;  // radians
  int data_samples = 0;            // rows of the data term
  int unthinned_samples = 0;       // rows before thinning (data_samples if not)
  int split_triangles = 0;         // mesh triangles with interior samples
  int min_samples_per_basis = 0;   // fewest data samples in one support
  int min_vertices_per_basis = 0;  // fewest input vertices in one support
  // The measurement of this round (surface samples; mesh -> surface as the
  // parametric bound |F(u_i) - x_i| unless `closest_points`).
  int64_t surface_samples = 0;
  bool closest_points = false;
  // With closest_points: the mesh samples (the vertices, points inside the
  // triangles, and those the bound added), and an upper bound of the true
  // mesh -> surface maximum anywhere on the mesh
  // (SurfaceDeviation::mesh_to_surface_max_bound_percent); 0 otherwise.
  int64_t mesh_samples = 0;
  double mesh_to_surface_max_bound_percent = 0;
  // The round's own rms (its lattice and the parametric bound), before the
  // dense measurement replaced it (closest_points) or not.
  double round_rmse_percent = 0;
  // The same with the mesh -> surface half estimated to first order (the
  // residuals' components along the mesh's vertex normals).
  double estimated_rmse_percent = 0;
  // A round that folded where it otherwise met the target, its folds
  // repaired (core/fit/fold_repair.h): the folded area at the final
  // measurement's lattice before, the steps the repair tried, and whether
  // its result was kept (`fold_repaired`: the folds at least halved, the
  // control points moved; FoldRepairResult::changed); 0 / 0 / false for a
  // round not tried. The round's figures above are those after a kept
  // repair.
  double folded_before_repair_percent = 0;
  int fold_repair_iterations = 0;
  bool fold_repaired = false;
};

struct FitResult {
  // The model; its statistics carry no wall-clock times, so the same input
  // and options give the same model bytes.
  SplineModel model;
  // Seconds per stage, summed over the rounds.
  StageTimings timings;
  // One entry per round of model.statistics.rounds.
  std::vector<RoundDetails> round_details;
  // Per input vertex: |x_i - F(u_i)| in percent of the largest side.
  Eigen::VectorXd vertex_errors_percent;
  // An open part's trims: its boundary loops at their sphere parameters
  // (core/spline/model.h); empty for a closed part.
  std::vector<TrimLoop> trims;
  // Why the target was not reached (empty when it was).
  std::string shortfall;
  // The input's sharp features at FitOptions::feature_angle_degrees.
  MeshFeatures features;
  // Vertices of the mesh the fit parameterized and fitted: the input's, or
  // its split's (FitOptions::map_vertices).
  int map_vertices = 0;
  // FitOptions::retry_map_vertices: a second fit on the split input was run
  // (its seconds are in `timings`), and whether it is the one returned.
  bool split_retry_run = false;
  bool split_retry_returned = false;
  // FitOptions::retry_lambda_factors: how many fits with a smaller lambda
  // were run (their seconds are in `timings`); the returned model's lambda
  // is in its statistics' options.
  int lambda_retries_run = 0;
  // Whether the model is the round on the feature corners' knot clusters
  // (core/knots/feature_knots.h), which keeps those features sharp.
  bool features_kept = false;
  // model.statistics.reached_target: the target was met.
  bool reached_target() const { return model.statistics.reached_target; }
};

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_FIT_RESULT_H_
