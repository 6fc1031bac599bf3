// Which round a fit that misses its target returns: IsBetterFallback's
// order over the rounds, the candidates a fit keeps as its rounds run (the
// best by that order, and the most accurate), and the choice between them
// once the fit ends, each measured densely as a reached round is.
#ifndef SDCB_CORE_FIT_FALLBACK_ROUND_H_
#define SDCB_CORE_FIT_FALLBACK_ROUND_H_

#include <Eigen/Core>
#include <functional>
#include <optional>

#include "sdcb/core/common/status.h"
#include "sdcb/core/fit/fit_result.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

// Whether round `a` is a better one to return than round `b` when the
// target is missed (FitOptions::fallback_accepts_folds): without folds
// first unless `accept_folds`, then the smaller rms.
bool IsBetterFallback(const RoundStatistics& a, const RoundStatistics& b,
                      bool accept_folds);

// A round kept to be returned if the target is missed.
struct FallbackCandidate {
  SplineModel model;
  Eigen::VectorXd vertex_errors;  // per input vertex
  // Whether the vertex errors are |F(u_i) - x_i| at every vertex, not a
  // thinned round's cell values.
  bool vertex_errors_exact = true;
};

// The round a fit returns: its model and vertex errors in a FitResult, and
// whether those errors are exact.
struct ReturnedRound {
  FitResult* result = nullptr;
  bool* vertex_errors_exact = nullptr;
};

class FallbackRounds {
 public:
  explicit FallbackRounds(bool accept_folds) : accept_folds_(accept_folds) {}

  // Offers the round of `model` (its statistics' final_result): kept when it
  // is the best so far by IsBetterFallback, or the most accurate.
  void Offer(const SplineModel& model, const Eigen::VectorXd& vertex_errors,
             bool vertex_errors_exact);
  // Forgets every round offered.
  void Clear();

  // For a fit that missed its target (`returned`'s shortfall says why; its
  // model is the last round): returns its best round (IsBetterFallback),
  // measured again as a reached one is, by `measure_returned` (densely,
  // with the closest points: the rounds' own measurements are coarser and
  // see about a third of the small folds; it sets reached_target when that
  // meets the target). A round kept for having no folds in its round's
  // measurement that folds when measured densely has no claim over a more
  // accurate round: the most accurate is measured too, and returned when
  // its rms is smaller. The shortfall then names the returned round and its
  // dense figures.
  Status ReturnBest(const ReturnedRound& returned,
                    const std::function<Status()>& measure_returned) const;

 private:
  bool accept_folds_;
  std::optional<FallbackCandidate> best_;
  std::optional<FallbackCandidate> most_accurate_;
};

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_FALLBACK_ROUND_H_
