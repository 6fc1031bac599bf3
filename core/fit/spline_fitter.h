// The adaptive fitting driver (paper Algorithm 2): parameterize the mesh on
// the sphere, place knots where the surface bends (round 0) or where the fit
// is worst (later rounds) by a spherical CVT, build the degree-k DCB basis on
// the knots' Delaunay configurations, solve for the control points by
// regularized least squares, and repeat until the error reaches the target.
//
// SplineFitter is the stage as a class one can step (one round per AddRound),
// FitSphericalSpline the one-shot loop over it. This file is the driver; the
// ideas it drives live beside it in core/fit/: fit_mesh (the mesh and its
// map), feature_round (round 0 on the feature corners' clusters), fit_round
// (one round's steps) and round_problem (its least squares), stop_rule (the
// target and when to stop), fallback_round (the round a missed fit
// returns), retry_strategy (FitSphericalSpline's further fits), fit_progress
// (progress and timings), fit_result (what a fit returns).
//
// Errors are in percent of the largest side of the input's bounding box: the
// fit works in the normalized frame of ComputeNormalizingTransform, where
// that side is 1 (docs/ARCHITECTURE.md, docs/FITTING.md).
#ifndef SDCB_CORE_FIT_SPLINE_FITTER_H_
#define SDCB_CORE_FIT_SPLINE_FITTER_H_

#include <memory>

#include "sdcb/core/common/status.h"
#include "sdcb/core/fit/fallback_round.h"
#include "sdcb/core/fit/fit_options.h"
#include "sdcb/core/fit/fit_result.h"
#include "sdcb/core/mesh/hole_filling.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

class SplineFitter {
 public:
  // Checks the options (kInvalidArgument) and the mesh (it must pass
  // RequireClosedGenusZero: else its kUnsupported status), normalizes the
  // mesh, parameterizes it on the sphere and prepares round 0. `mesh` is
  // copied.
  static StatusOr<SplineFitter> Create(const TriangleMesh& mesh,
                                       FitOptions options);
  // The same for an open part with its holes filled (core/mesh/
  // hole_filling.h; a closed one is Create(filled.mesh)): the map and the
  // data term use the closed mesh, the fill's faces weighted low; errors,
  // folds and the model's source are the part's own, in the region its
  // boundary loops keep (FitResult::trims).
  static StatusOr<SplineFitter> Create(const FilledMesh& filled,
                                       FitOptions options);

  SplineFitter(SplineFitter&&) noexcept;
  SplineFitter& operator=(SplineFitter&&) noexcept;
  ~SplineFitter();

  // Runs one round: places the round's knots with the existing ones fixed,
  // builds the basis on their configurations, solves for the control points
  // and measures the surface against the mesh. The fit is finished when a round
  // meets the target with no fold (confirmed by the denser final measurement),
  // after max_rounds, or when a round would exceed max_control_points (that
  // round is not added). A fit that misses the target returns the round with
  // the smallest rms among those without folds (or, if every round folds,
  // among all), with FitResult::shortfall saying why. kInvalidArgument
  // when called after finished().
  Status AddRound();

  // No further round will run: the target is reached or a limit is hit.
  bool finished() const;

  // From now on, AddRound holds back a round (after round 0) that would
  // have more than `control_points` control points: it returns before the
  // round's basis with nothing added, and paused() is true. PauseAbove
  // again (0: never) resumes; the next AddRound places that round again,
  // the same way. AddRound while paused is kInvalidArgument.
  void PauseAbove(int control_points);
  bool paused() const;
  // The control points of the round held back (when paused()).
  int held_control_points() const;
  // The cap on control points from now on (FitOptions::max_control_points,
  // also as the model records it).
  void SetMaxControlPoints(int control_points);

  // Whether the finished fit reached its target.
  bool reached_target() const;
  // Rounds run so far.
  int rounds() const;
  // The model of the latest round (its control points, knots and
  // statistics); valid after the first AddRound.
  const SplineModel& model() const;

  // The result; call once, after finished() (or, for the rounds so far and
  // their seconds, when paused()). Leaves the fitter empty.
  FitResult TakeResult();
  // Whether TakeResult was called.
  bool taken() const;

 private:
  struct State;
  explicit SplineFitter(std::unique_ptr<State> state);
  static StatusOr<SplineFitter> Create(const TriangleMesh& mesh,
                                       const FilledMesh* filled,
                                       FitOptions options);
  std::unique_ptr<State> state_;
};

// Fits `mesh`: SplineFitter::Create, AddRound until finished, TakeResult,
// and once more on the split input when FitOptions::retry_map_vertices asks.
// The result is the same for any thread count.
StatusOr<FitResult> FitSphericalSpline(const TriangleMesh& mesh,
                                       const FitOptions& options = {});
// Fits an open part with its holes filled (SplineFitter::Create(filled)):
// the loop, then, unless FitOptions::map_vertices or retry_map_vertices ask
// for one fit, the fits with a smaller lambda while it misses and folds (a
// thin part), never on a split. A closed `filled`: the above.
StatusOr<FitResult> FitSphericalSpline(const FilledMesh& filled,
                                       const FitOptions& options = {});

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_SPLINE_FITTER_H_
