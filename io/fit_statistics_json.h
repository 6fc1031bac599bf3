// FitStatistics <-> JSON, in the shape of the `fit --json` report (DESIGN.md):
//   {"rounds": [{"round", "knots", "control_points", "rmse_percent",
//                "max_error_percent", "seconds"}, ...],
//    "final": {same keys},
//    "timings": {"parameterization", "knot_placement", "configurations",
//                "basis", "solve", "total"},
//    "options": {"degree", "rmse_percent", "knots_per_round", "max_rounds",
//                "lambda"}}
// Used by the .sdcb STAT chunk and by `sdcb dump`. Doubles are written with
// the shortest representation that parses back to the same bits.
#ifndef SDCB_IO_FIT_STATISTICS_JSON_H_
#define SDCB_IO_FIT_STATISTICS_JSON_H_

#include <nlohmann/json.hpp>

#include "sdcb/core/common/status.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

nlohmann::json FitStatisticsToJson(const FitStatistics& statistics);

// Reads what FitStatisticsToJson wrote. Unknown keys are ignored (so the
// record can grow); a missing key, a wrong type or an integer outside int
// range gives kInvalidInput naming the key.
StatusOr<FitStatistics> FitStatisticsFromJson(const nlohmann::json& json);

}  // namespace sdcb

#endif  // SDCB_IO_FIT_STATISTICS_JSON_H_
