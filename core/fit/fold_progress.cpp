#include "sdcb/core/fit/fold_progress.h"

namespace sdcb {

bool FoldProgress::Stalls(int knots, double folded_area_percent) {
  if (!(folded_area_percent > 0)) return false;
  if (knots_at_least_ == 0 || folded_area_percent < least_folded_percent_) {
    least_folded_percent_ = folded_area_percent;
    knots_at_least_ = knots;
    return false;
  }
  return knots >= kKnotGrowth * knots_at_least_ &&
         folded_area_percent >= kMinFoldedPercent;
}

}  // namespace sdcb
