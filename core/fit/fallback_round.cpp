#include "sdcb/core/fit/fallback_round.h"

#include <string>
#include <utility>

#include "sdcb/core/fit/fit_progress.h"

namespace sdcb {
namespace {

// The returned round as a candidate (its model with the fit's statistics).
FallbackCandidate AsCandidate(const ReturnedRound& r) {
  return {r.result->model, r.result->vertex_errors_percent,
          *r.vertex_errors_exact};
}

// Returns `c`'s round: its model and vertex errors, with the statistics of
// the fit (every round) and `c`'s round as the final one.
void Return(const FallbackCandidate& c, const ReturnedRound& r) {
  FitResult& result = *r.result;
  FitStatistics stats = std::move(result.model.statistics);
  result.model = c.model;
  stats.final_result = c.model.statistics.final_result;
  result.model.statistics = std::move(stats);
  result.vertex_errors_percent = c.vertex_errors;
  *r.vertex_errors_exact = c.vertex_errors_exact;
}

}  // namespace

bool IsBetterFallback(const RoundStatistics& a, const RoundStatistics& b,
                      bool accept_folds) {
  if (!accept_folds &&
      (a.folded_area_percent == 0) != (b.folded_area_percent == 0)) {
    return a.folded_area_percent == 0;
  }
  return a.rmse_percent < b.rmse_percent;
}

void FallbackRounds::Offer(const SplineModel& model,
                           const Eigen::VectorXd& vertex_errors,
                           bool vertex_errors_exact) {
  const RoundStatistics& rs = model.statistics.final_result;
  if (!best_ || IsBetterFallback(rs, best_->model.statistics.final_result,
                                 accept_folds_)) {
    best_ = FallbackCandidate{model, vertex_errors, vertex_errors_exact};
  }
  if (!most_accurate_ ||
      IsBetterFallback(rs, most_accurate_->model.statistics.final_result,
                       /*accept_folds=*/true)) {
    most_accurate_ =
        FallbackCandidate{model, vertex_errors, vertex_errors_exact};
  }
}

void FallbackRounds::Clear() {
  best_.reset();
  most_accurate_.reset();
}

Status FallbackRounds::ReturnBest(
    const ReturnedRound& returned,
    const std::function<Status()>& measure_returned) const {
  FitResult& result = *returned.result;
  const int last = result.model.statistics.final_result.round;
  if (best_ &&
      IsBetterFallback(best_->model.statistics.final_result,
                       result.model.statistics.final_result, accept_folds_)) {
    Return(*best_, returned);
  }
  const bool kept_unfolded =
      result.model.statistics.final_result.folded_area_percent == 0;
  SDCB_RETURN_IF_ERROR(measure_returned());
  if (result.model.statistics.reached_target) return Status::Ok();
  const RoundStatistics kept = result.model.statistics.final_result;
  std::string why =
      kept_unfolded && !accept_folds_
          ? "the most accurate without folds in its round's measurement"
          : "the most accurate";
  if (kept_unfolded && kept.folded_area_percent > 0 && most_accurate_ &&
      most_accurate_->model.statistics.final_result.round != kept.round) {
    const FallbackCandidate other = AsCandidate(returned);
    Return(*most_accurate_, returned);
    SDCB_RETURN_IF_ERROR(measure_returned());
    if (result.model.statistics.reached_target) return Status::Ok();
    if (result.model.statistics.final_result.rmse_percent < kept.rmse_percent) {
      why = "the most accurate (round " + std::to_string(kept.round) +
            ", without folds in its round's measurement, folds " +
            ShortNumber(kept.folded_area_percent) +
            " % of its area when measured densely)";
    } else {
      Return(other, returned);
    }
  }
  const RoundStatistics& r = result.model.statistics.final_result;
  if (r.round != last) {
    result.shortfall +=
        "; returned round " + std::to_string(r.round) + " instead, " + why;
  }
  result.shortfall +=
      " (returned surface, measured densely: rms " +
      ShortNumber(r.rmse_percent) + " %, max " +
      ShortNumber(r.max_error_percent) + " %" +
      (r.boundary_error_percent >= 0
           ? ", boundary " + ShortNumber(r.boundary_error_percent) + " %"
           : std::string()) +
      (r.folded_area_percent > 0
           ? ", folded " + ShortNumber(r.folded_area_percent) + " % of its area"
           : std::string()) +
      ")";
  return Status::Ok();
}

}  // namespace sdcb
