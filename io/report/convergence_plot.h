// The convergence plot of a fit (like the paper's Fig. 11): RMSE and max
// error per round on a log scale, with the target line, as a standalone SVG.
#ifndef SDCB_IO_REPORT_CONVERGENCE_PLOT_H_
#define SDCB_IO_REPORT_CONVERGENCE_PLOT_H_

#include <string>

#include "sdcb/core/common/status.h"
#include "sdcb/core/spline/spline_model.h"

namespace sdcb {

// The SVG text for `statistics` (at least one round); `title` is shown on top.
std::string ConvergencePlotSvg(const FitStatistics& statistics,
                               const std::string& title);

// Writes ConvergencePlotSvg atomically to `path`.
Status WriteConvergencePlot(const FitStatistics& statistics,
                            const std::string& title, const std::string& path);

}  // namespace sdcb

#endif  // SDCB_IO_REPORT_CONVERGENCE_PLOT_H_
