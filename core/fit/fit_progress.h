// What a fit reports while it runs: the share of the fit done
// (FitProgress::fraction, from a model of where a fit's time goes), the
// wall time per stage (StageTimings), and its numbers in messages.
#ifndef SDCB_CORE_FIT_FIT_PROGRESS_H_
#define SDCB_CORE_FIT_FIT_PROGRESS_H_

#include <chrono>
#include <functional>
#include <string>
#include <utility>

#include "sdcb/core/common/stopwatch.h"
#include "sdcb/core/fit/fit_options.h"
#include "sdcb/core/fit/fit_result.h"

namespace sdcb {

// Adds the seconds of the stages a round runs (knot placement to measure)
// of `from` to `to`; the parameterization and the total are the caller's.
void AddRoundStages(const StageTimings& from, StageTimings* to);

// Progress model (FitProgress::fraction). The parameterization takes about
// this share of a typical fit (bunny00: 1.9 s of 4.4 s; smaller meshes less).
constexpr double kParameterizationShare = 0.3;
// Rounds assumed before two rounds show the error's decay.
constexpr int kInitialRoundGuess = 5;

// Turns a fit's stages into FitProgress reports for FitOptions::progress:
// the parameterization is the first kParameterizationShare, the rounds
// share the rest equally (as many as estimated so far), and within a round
// each stage starts at its typical share of a round's time.
class ProgressReporter {
 public:
  explicit ProgressReporter(std::function<void(const FitProgress&)> callback)
      : callback_(std::move(callback)) {}

  // The rounds the fit is expected to run (the stop rule's estimate).
  int estimated_rounds() const { return estimated_rounds_; }
  void set_estimated_rounds(int rounds) { estimated_rounds_ = rounds; }

  // `within`: the finished share of the parameterization (0 for kDone).
  void Report(FitStage stage, int round, double within) const;
  // The start of a round's stage (knot placement to measure).
  void StartRoundStage(FitStage stage, int round) const;

 private:
  std::function<void(const FitProgress&)> callback_;
  int estimated_rounds_ = kInitialRoundGuess;
};

// A number with four significant digits, for messages.
std::string ShortNumber(double value);

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_FIT_PROGRESS_H_
