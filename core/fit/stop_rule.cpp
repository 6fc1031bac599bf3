#include "sdcb/core/fit/stop_rule.h"

#include <algorithm>
#include <cmath>

#include "sdcb/core/fit/fit_progress.h"

namespace sdcb {
namespace {

// Rounds before a fit may stop because its error falls too slowly.
constexpr int kMinRoundsBeforeRateStop = 5;
// The share of the knots a power law through the last two rounds puts at the
// rms target that a round adds when that is less than a whole round: the
// rms falls faster than that law says (bunny00, --rmse 0.067: the law
// through 200 and 300 knots has exponent 1.24; 300 to 369 knots fell with
// 1.66), so the whole difference overshoots the target (0.0613 % at 369
// knots; 0.0646 % at 360 with 0.7).
constexpr double kLastRoundShare = 0.7;
// Fold rounds stop early when, after this many, the folded area has not
// shrunk to kFoldShrink of what it was when they began (measured on CGAL's
// meshes: where folds went away they had halved by then; where they stayed,
// 0.2 % on the cow and camel, they had shrunk by 10 % at most).
constexpr int kFoldRoundsToShrink = 2;

// An open part's boundary target, as a share of the Hausdorff target: half
// of it, less the export's default tolerance (0.1 %, a tenth of the default
// Hausdorff target), whose boundary edges are chords within the tolerance
// of the trims' images: the export's boundary then stays within half the
// Hausdorff target of the part's (docs/PARTS.md).
constexpr double kBoundaryTargetShare = 0.4;
constexpr double kFoldShrink = 0.5;

}  // namespace

FitTarget FitTarget::Of(const FitOptions& options) {
  FitTarget target;
  target.rmse_percent = options.rmse_percent;
  target.max_error_percent = MaxErrorTarget(options);
  if (target.max_error_percent >= 0) {
    target.boundary_percent = kBoundaryTargetShare * target.max_error_percent;
  }
  return target;
}

TargetCheck CompareWithTarget(const FitTarget& target, double rms,
                              double max_error, double folded,
                              double boundary) {
  TargetCheck check;
  check.rms = rms <= target.rmse_percent;
  check.max_error =
      target.max_error_percent < 0 || max_error <= target.max_error_percent;
  check.unfolded = folded == 0;
  check.boundary = boundary < 0 || target.boundary_percent < 0 ||
                   boundary <= target.boundary_percent;
  return check;
}

TargetCheck CompareWithTarget(const FitTarget& target,
                              const RoundStatistics& round) {
  return CompareWithTarget(target, round.rmse_percent, round.max_error_percent,
                           round.folded_area_percent,
                           round.boundary_error_percent);
}

int RoundsToTarget(const std::vector<RoundStatistics>& rounds,
                   const FitTarget& target) {
  const int n = static_cast<int>(rounds.size());
  if (n < 2) return -1;
  const int window = std::min(3, n - 1);
  const TargetCheck now = CompareWithTarget(target, rounds[n - 1]);
  // The rounds an error still above `goal` needs at its decay per round.
  auto rounds_to = [&](bool met, double goal, double RoundStatistics::*error) {
    if (met) return 0.0;
    const double last = rounds[n - 1].*error;
    const double decay =
        std::pow(last / (rounds[n - 1 - window].*error), 1.0 / window);
    if (!(decay > 0 && decay < 1)) return -1.0;
    return std::ceil(std::log(goal / last) / std::log(decay));
  };
  const double for_rms =
      rounds_to(now.rms, target.rmse_percent, &RoundStatistics::rmse_percent);
  // The Hausdorff distance counts once the rms is met: before, the rounds
  // bound its mesh -> surface half coarsely (core/fit/fit_round.h).
  const double for_max =
      for_rms != 0 ? 0.0
                   : rounds_to(now.max_error, target.max_error_percent,
                               &RoundStatistics::max_error_percent);
  // An open part's boundary distance, likewise.
  const double for_boundary =
      for_rms != 0 ? 0.0
                   : rounds_to(now.boundary, target.boundary_percent,
                               &RoundStatistics::boundary_error_percent);
  if (for_rms < 0 || for_max < 0 || for_boundary < 0) return -1;
  return static_cast<int>(
      std::clamp(std::max({for_rms, for_max, for_boundary}), 1.0, 1e6));
}

int KnotsToTarget(const std::vector<RoundStatistics>& rounds,
                  const FitTarget& target, int planned) {
  // rms = c knots^-p through the last two rounds (both above the rms
  // target, neither folded, the last within the Hausdorff target) gives the
  // knots at the target; the round adds kLastRoundShare of the difference
  // when that is less than planned. A round still above the Hausdorff
  // target (or an open part's boundary target) is not sized: that distance
  // (at a crease, a corner) falls unevenly, and rounds sized by it come
  // short many times over. An open part's round above the Hausdorff target
  // is sized: its largest distances lie along the boundary, where the pin
  // holds the surface to the loop (the cut bunny at 210 knots: 1.23 %
  // measured densely, two thirds of its 400 farthest samples within 5 % of
  // the diagonal of the boundary), and fall with the rms (0.74 % at 231
  // knots).
  const size_t n = rounds.size();
  if (n < 2) return planned;
  const RoundStatistics& a = rounds[n - 2];
  const RoundStatistics& b = rounds[n - 1];
  const TargetCheck last = CompareWithTarget(target, b);
  const bool open_part = b.boundary_error_percent >= 0;
  if (!(b.knots > a.knots && a.rmse_percent > b.rmse_percent && !last.rms &&
        a.folded_area_percent == 0 && last.unfolded &&
        (last.max_error || open_part) && last.boundary)) {
    return planned;
  }
  const double p = std::log(a.rmse_percent / b.rmse_percent) /
                   std::log(static_cast<double>(b.knots) / a.knots);
  const double at_target =
      b.knots * std::pow(b.rmse_percent / target.rmse_percent, 1 / p);
  const double needed = kLastRoundShare * (at_target - b.knots);
  if (!(needed < planned)) return planned;
  return std::max(kMinFoldKnots, static_cast<int>(std::ceil(needed)));
}

StopRule::StopRule(const FitOptions& options)
    : target_(FitTarget::Of(options)),
      max_rounds_(options.max_rounds),
      max_fold_rounds_(options.max_fold_rounds),
      max_control_points_(options.max_control_points),
      initial_knots_(options.initial_knots),
      knots_per_round_(options.knots_per_round),
      knots_growth_(options.knots_growth) {}

int StopRule::RoundKnots(const std::vector<RoundStatistics>& rounds,
                         int knots) const {
  if (rounds.empty() && initial_knots_ > 0) return initial_knots_;
  if (fold_round_) return std::max(kMinFoldKnots, knots_per_round_ / 4);
  const int grown = static_cast<int>(
      std::min<double>(knots_growth_ * static_cast<double>(knots), 1e7));
  return KnotsToTarget(rounds, target_, std::max(knots_per_round_, grown));
}

std::optional<std::string> StopRule::ControlPointLimit(
    int round, int control_points) const {
  if (round == 0 || control_points <= max_control_points_) return std::nullopt;
  return "the next round would exceed " + std::to_string(max_control_points_) +
         " control points";
}

std::optional<std::string> StopRule::AfterMissedRound(
    const std::vector<RoundStatistics>& rounds, int* estimated_rounds) {
  // Met the rms target but folded: the next rounds put fewer knots, only
  // where the surface folds, a few times at most.
  const RoundStatistics& rs = rounds.back();
  const int round = static_cast<int>(rounds.size()) - 1;
  const TargetCheck check = CompareWithTarget(target_, rs);
  const bool only_folds = check.rms && !check.unfolded;
  const std::string folds_left =
      "the surface still folds (narrow creases or thin parts the spline "
      "cannot follow yet)";
  if (only_folds && fold_rounds_in_a_row_ == 0) {
    folds_when_fold_rounds_began_ = rs.folded_area_percent;
  }
  if (only_folds && fold_rounds_ >= max_fold_rounds_) return folds_left;
  if (fold_progress_.Stalls(rs.knots, rs.folded_area_percent)) {
    return folds_left + "; its folds do not shrink as knots are added (" +
           ShortNumber(fold_progress_.least_folded_percent()) +
           " % of its area at " +
           std::to_string(fold_progress_.knots_at_least()) + " knots, " +
           ShortNumber(rs.folded_area_percent) + " % at " +
           std::to_string(rs.knots) + ")";
  }
  // Fold rounds that have not shrunk the folds give way to an ordinary
  // round (knots where the error is, and where it folds).
  const bool folds_stay =
      fold_rounds_in_a_row_ >= kFoldRoundsToShrink &&
      rs.folded_area_percent > kFoldShrink * folds_when_fold_rounds_began_;
  if (round + 1 == max_rounds_) {
    return only_folds ? folds_left
                      : "the target was not reached within " +
                            std::to_string(max_rounds_) + " rounds";
  }
  fold_round_ = only_folds && !folds_stay;
  if (fold_round_) {
    ++fold_rounds_;
    ++fold_rounds_in_a_row_;
  } else {
    fold_rounds_in_a_row_ = 0;
  }
  // A fit whose error falls too slowly to reach the target within the
  // rounds left (judged after six rounds) stops now rather than later.
  const int needed = RoundsToTarget(rounds, target_);
  if (needed >= 0) {
    *estimated_rounds =
        std::min(max_rounds_, static_cast<int>(rounds.size()) + needed);
  }
  const int left = max_rounds_ - round - 1;
  if (!only_folds && round >= kMinRoundsBeforeRateStop &&
      (needed < 0 || needed > left)) {
    const std::string error =
        !check.rms ? std::string("the error")
        : !check.max_error
            ? "the Hausdorff distance (" + ShortNumber(rs.max_error_percent) +
                  " %, target " + ShortNumber(target_.max_error_percent) + " %)"
            : "the boundary's distance (" +
                  ShortNumber(rs.boundary_error_percent) + " %, target " +
                  ShortNumber(target_.boundary_percent) + " %)";
    return needed < 0 ? error + " stopped falling"
                      : "at its current rate " + error + " needs about " +
                            std::to_string(needed) +
                            " more rounds, more than --max-rounds leaves (" +
                            std::to_string(left) + ")";
  }
  return std::nullopt;
}

}  // namespace sdcb
