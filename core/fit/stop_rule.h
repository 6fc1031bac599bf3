// The fit's target and the rules that read its rounds against it: whether a
// round reaches the target (rms and Hausdorff distance at most their
// targets, nothing folded: CompareWithTarget, the one comparison of errors
// with the target), how many knots the next round adds, and when a fit that
// has not reached it stops (fold rounds, stalled folds, max_rounds, the
// control-point cap, an error that falls too slowly).
#ifndef SDCB_CORE_FIT_STOP_RULE_H_
#define SDCB_CORE_FIT_STOP_RULE_H_

#include <optional>
#include <string>
#include <vector>

#include "sdcb/core/fit/fit_options.h"
#include "sdcb/core/fit/fold_progress.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

// The fewest knots a round adds: rounds that only remove folds, and rounds
// halved because the knots had no room for more.
constexpr int kMinFoldKnots = 10;

// What a fit must reach, percent of the largest bounding-box side.
struct FitTarget {
  double rmse_percent = 0;
  double max_error_percent = -1;  // the Hausdorff distance's; < 0: none
  // An open part's boundary distance (core/measure/boundary_deviation.h):
  // 0.4 of the Hausdorff target (stop_rule.cpp); < 0: none.
  double boundary_percent = -1;

  // FitOptions::rmse_percent and MaxErrorTarget.
  static FitTarget Of(const FitOptions& options);
};

// Which parts of the target a measurement meets.
struct TargetCheck {
  bool rms = false;        // rms <= target
  bool max_error = false;  // Hausdorff <= its target, or it has none
  bool unfolded = false;   // no folded area
  bool boundary = true;    // boundary distance <= its target, or no boundary
  bool reached() const { return rms && max_error && unfolded && boundary; }
};

// The errors (rms, Hausdorff distance, folded area, an open part's boundary
// distance or -1, percent) against the target.
TargetCheck CompareWithTarget(const FitTarget& target, double rms,
                              double max_error, double folded,
                              double boundary = -1);
TargetCheck CompareWithTarget(const FitTarget& target,
                              const RoundStatistics& round);

// Rounds still needed at the recent rate of decay of each error still above
// its target (the rms; the Hausdorff distance once the rms is met), over the
// last (up to) three rounds; -1 if an error does not fall or there are fewer
// than two rounds.
int RoundsToTarget(const std::vector<RoundStatistics>& rounds,
                   const FitTarget& target);

// The knots the next round adds: `planned`, or fewer (at least
// kMinFoldKnots) when the power law through the last two rounds says fewer
// reach the rms target.
int KnotsToTarget(const std::vector<RoundStatistics>& rounds,
                  const FitTarget& target, int planned);

// Whether a fit that has not reached its target goes on, and whether its
// next round places knots only where the surface folds (a round that met
// the rms target but folded).
class StopRule {
 public:
  explicit StopRule(const FitOptions& options);

  // The knots round `round` adds to a fit of `knots` knots after `rounds`.
  int RoundKnots(const std::vector<RoundStatistics>& rounds, int knots) const;

  // Why a round `round` of `control_points` control points is not added
  // (above max_control_points; round 0 always is), or nullopt.
  std::optional<std::string> ControlPointLimit(int round,
                                               int control_points) const;

  // Whether a round `round` of `control_points` control points is held back
  // for the caller to decide (SplineFitter::PauseAbove): more than
  // `pause_above` of them, round 0 never; 0 holds none back.
  bool Pauses(int round, int control_points) const {
    return round > 0 && pause_above_ > 0 && control_points > pause_above_;
  }
  void set_pause_above(int control_points) { pause_above_ = control_points; }
  void set_max_control_points(int control_points) {
    max_control_points_ = control_points;
  }

  // After a round that did not reach the target (the last of `rounds`):
  // why the fit stops there (its shortfall), or nullopt when it goes on.
  // `estimated_rounds` becomes the rounds the fit will run at the recent
  // rate (RoundsToTarget, at most max_rounds) when the fit gets that far
  // and the rate says (else it is left as it is).
  std::optional<std::string> AfterMissedRound(
      const std::vector<RoundStatistics>& rounds, int* estimated_rounds);

  // Whether the next round places knots only where the surface folds.
  bool fold_round() const { return fold_round_; }
  const FitTarget& target() const { return target_; }

 private:
  FitTarget target_;
  int max_rounds_;
  int max_fold_rounds_;
  int max_control_points_;
  int pause_above_ = 0;
  int initial_knots_;
  int knots_per_round_;
  double knots_growth_;
  bool fold_round_ = false;
  int fold_rounds_ = 0;
  int fold_rounds_in_a_row_ = 0;
  double folds_when_fold_rounds_began_ = 0.0;
  // Whether the folds shrink as knots are added.
  FoldProgress fold_progress_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_STOP_RULE_H_
