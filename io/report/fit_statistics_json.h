// FitStatistics <-> JSON: the model's record of its fit (the .sdcb STAT
// chunk, `sdcb dump`'s "statistics"), and the `fit --json` report, which adds
// the wall-clock times the model does not keep (keys: docs/CLI.md, `sdcb fit`):
//   {"rounds": [ROUND, ...], "final": ROUND,
//    "options": {every recorded option of core/fit/fit_options.h's
//                FitOptionTable, under its key},
//    "error_measure": "dense_two_sided" | "vertices",
//    "reached_target": bool}
//   ROUND = {"round", "knots", "control_points", "rmse_percent",
//            "max_error_percent", "vertex_rmse_percent",
//            "vertex_max_error_percent", "folded_area_percent"}
// The report adds "seconds" to every ROUND, "timings": {"parameterization",
// "knot_placement", "configurations", "basis", "solve", "total"} and
// "round_details", "basis_form", "features": {"angle_degrees", "edges",
// "curves", "corners", "used"} (the input's sharp features,
// core/mesh/feature_curves.h; "used": whether the fit kept them sharp) and,
// when the target was missed, "shortfall". Doubles are written with the
// shortest representation that parses back to the same bits.
#ifndef SDCB_IO_REPORT_FIT_STATISTICS_JSON_H_
#define SDCB_IO_REPORT_FIT_STATISTICS_JSON_H_

#include <nlohmann/json.hpp>

#include "sdcb/core/common/status.h"
#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

nlohmann::json FitStatisticsToJson(const FitStatistics& statistics);

// Reads what FitStatisticsToJson wrote, and the STAT object of format
// version 1 (timings and seconds ignored; error_measure "vertices"; the
// vertex errors equal to the errors; options it did not record 0 / false;
// reached_target from the final RMSE and the target). Unknown keys are
// ignored; a missing required key, a wrong type or an integer outside int
// range gives kInvalidInput naming the key.
StatusOr<FitStatistics> FitStatisticsFromJson(const nlohmann::json& json);

// The `fit --json` report of `fit` (keys above; ordered for reading).
nlohmann::ordered_json FitReportToJson(const FitResult& fit);

}  // namespace sdcb

#endif  // SDCB_IO_REPORT_FIT_STATISTICS_JSON_H_
