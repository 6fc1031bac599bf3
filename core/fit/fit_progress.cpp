#include "sdcb/core/fit/fit_progress.h"

#include <algorithm>
#include <iomanip>
#include <locale>
#include <sstream>

namespace sdcb {
namespace {

// Where each stage starts within a round, as a share of the round's time
// (bunny00, degree 4).
double RoundStageStart(FitStage stage) {
  switch (stage) {
    case FitStage::kKnotPlacement:
      return 0.0;
    case FitStage::kConfigurations:
      return 0.2;
    case FitStage::kBasis:
      return 0.25;
    case FitStage::kSolve:
      return 0.55;
    case FitStage::kMeasure:
      return 0.75;
    default:
      return 0.0;
  }
}

}  // namespace

void AddRoundStages(const StageTimings& from, StageTimings* to) {
  to->knot_placement += from.knot_placement;
  to->configurations += from.configurations;
  to->basis += from.basis;
  to->solve += from.solve;
  to->measure += from.measure;
}

void ProgressReporter::Report(FitStage stage, int round, double within) const {
  if (!callback_) return;
  FitProgress p;
  p.stage = stage;
  p.round = round;
  if (stage == FitStage::kParameterization) {
    p.fraction = kParameterizationShare * within;
  } else if (stage == FitStage::kDone) {
    p.fraction = 1.0;
  } else {
    const double rounds = std::max(estimated_rounds_, round + 1);
    p.fraction = kParameterizationShare +
                 (1.0 - kParameterizationShare) * (round + within) / rounds;
  }
  p.fraction = std::clamp(p.fraction, 0.0, 1.0);
  callback_(p);
}

void ProgressReporter::StartRoundStage(FitStage stage, int round) const {
  Report(stage, round, RoundStageStart(stage));
}

std::string ShortNumber(double value) {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out << std::setprecision(4) << value;
  return out.str();
}

}  // namespace sdcb
