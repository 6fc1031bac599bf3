// One round of the fit (paper Algorithm 2's loop body), in its steps: the
// round's knots placed by a spherical CVT of the density with the fit's
// knots fixed (placed again with the density floored when the basis on them
// has a hole), their configurations, the least-squares problem on them
// (core/fit/round_problem.h) solved, the surface measured (its small folds
// repaired, core/fit/fold_repair.h) and, when it may meet the target,
// measured again densely (the final measurement); then the density of the
// next round's knots, where the error is.
#ifndef SDCB_CORE_FIT_FIT_ROUND_H_
#define SDCB_CORE_FIT_FIT_ROUND_H_

#include <Eigen/Core>
#include <optional>
#include <string>

#include "sdcb/core/common/status.h"
#include "sdcb/core/fit/fit_mesh.h"
#include "sdcb/core/fit/fit_options.h"
#include "sdcb/core/fit/fit_progress.h"
#include "sdcb/core/fit/fit_result.h"
#include "sdcb/core/fit/round_problem.h"
#include "sdcb/core/fit/stop_rule.h"
#include "sdcb/core/knots/spherical_cvt.h"
#include "sdcb/core/measure/surface_deviation.h"
#include "sdcb/core/mesh/feature_curves.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb {

// What a round reads: the fit's options, mesh and features, the stop rule's
// limits, and where it reports its stages.
struct RoundContext {
  const FitOptions& options;
  const FitMesh& fit;
  const MeshFeatures& features;
  const StopRule& stop;
  const ProgressReporter& progress;
  int round = 0;
};

// Steps 1-3: the round's knots, their configurations and the problem on
// them; or, with no problem, why the fit stops before the round (no room
// for its knots, or more control points than the cap).
struct PlacedRound {
  KnotPlacement placement;
  DelaunayConfigurations configurations;
  std::optional<RoundProblem> problem;
  std::string shortfall;
  // Held back before its basis (StopRule::Pauses): no problem, no shortfall;
  // the control points it would have.
  bool paused = false;
  int held_control_points = 0;
};

// Places `new_knots` knots by `density` with `fixed_knots` fixed (as many
// as have room, halving down to kMinFoldKnots), or the feature clusters'
// `feature_knots` alone when not null (round 0 on the clusters), and builds
// the problem on them.
StatusOr<PlacedRound> PlaceRound(const RoundContext& context,
                                 const SphericalDensity& density,
                                 const Eigen::MatrixX3d& fixed_knots,
                                 int new_knots,
                                 const Eigen::MatrixX3d* feature_knots,
                                 RoundDetails* details);

// Steps 4-5: the solved and measured round.
struct SolvedRound {
  Eigen::MatrixX3d control_points;
  Eigen::MatrixX3d fitted;  // the data rows' values: problem.data * control
  std::optional<SphericalSpline> surface;
  // The round's own measurement, or the final one when it ran.
  SurfaceDeviation deviation;
  // F(u_i) at every vertex when known (unthinned samples, or a final
  // measurement), else empty.
  Eigen::MatrixX3d vertex_points;
  // The final measurement ran and met the target.
  bool reached = false;
};

// Solves `problem` (its basis moves into the round's surface) and measures
// the surface: the surface -> mesh half at a lattice, the mesh -> surface
// half bounded by the parametric residual at the data rows; small folds
// where the round otherwise meets the target repaired; the final
// measurement when nothing folds and the rms, or its first-order estimate,
// meets the target.
StatusOr<SolvedRound> SolveAndMeasure(const RoundContext& context,
                                      RoundProblem* problem,
                                      RoundDetails* details);

// `final_measurement` false: the surface -> mesh half only (a round bounds
// the other half at its data rows). `vertex_points`: F(u_i) per vertex,
// candidates of the final measurement's closest points, or null. An open
// part's boundary distance (core/measure/boundary_deviation.h, 16 samples
// per knot spacing along the trims) is set in either case.
StatusOr<SurfaceDeviation> MeasureFitSurface(
    const FitOptions& options, const FitMesh& fit,
    const SphericalSpline& surface, const Eigen::MatrixX3d* vertex_points,
    bool final_measurement);

// Per vertex of `fit`'s mesh, percent: |F(u_i) - x_i| where F(u_i) is known
// (`vertex_points` has a row per vertex), else the parametric residual of
// the row thinned `samples` kept for its cell.
Eigen::VectorXd RoundVertexErrors(const FitMesh& fit, const FitSamples& samples,
                                  const Eigen::MatrixX3d& fitted,
                                  const Eigen::MatrixX3d& vertex_points);

// The density of the next round's knots, where the round's error is: at a
// vertex the largest of its parametric residual (`vertex_errors`), those of
// the data samples inside its triangles, and the surface -> mesh distance
// of the surface samples nearest to it on the sphere; a folded sample
// counts as the largest error, and in a `fold_round` only those count.
// `density` keeps its values when there is no error.
void NextDensity(const FitOptions& options, const RoundProblem& problem,
                 const Eigen::MatrixX3d& fitted,
                 const Eigen::VectorXd& vertex_errors,
                 const SurfaceDeviation& deviation, bool fold_round,
                 FitMesh* fit, SphericalDensity* density);

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_FIT_ROUND_H_
