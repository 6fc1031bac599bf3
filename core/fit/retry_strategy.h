// FitSphericalSpline's further fits of the same input when the first one
// calls for them, and which fit it returns: the fit on the input split to
// FitOptions::retry_map_vertices (a smooth fit with more control points than
// the input has vertices, or a missed fit that folds on an input that does
// not pass through itself), then fits with the map's lambda times each of
// FitOptions::retry_lambda_factors while the fit to return still misses and
// folds (thin parts).
#ifndef SDCB_CORE_FIT_RETRY_STRATEGY_H_
#define SDCB_CORE_FIT_RETRY_STRATEGY_H_

#include <functional>
#include <optional>

#include "sdcb/core/common/status.h"
#include "sdcb/core/fit/fit_options.h"
#include "sdcb/core/fit/fit_result.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

// One whole fit of the input with the given options.
using FitRunner = std::function<StatusOr<FitResult>(const FitOptions&)>;

// Whether `candidate`, a further fit of the same input, should be returned
// instead of `current`, which misses its target: one that reaches; between
// two folded fits, the one folded less (the folds are what the further fits
// are for); else IsBetterFallback's order.
bool ReplacesMissedFit(const FitResult& candidate, const FitResult& current,
                       const FitOptions& options);

// `kept` gets the seconds of `other`, a fit of the same input not returned.
void AddSeconds(const FitResult& other, FitResult* kept);

// The options of the fit on `mesh` split to retry_map_vertices (smooth: no
// feature rounds), with at most `max_control_points` control points; nullopt
// when the map would not split `mesh` (SplitForMap).
std::optional<FitOptions> SplitFitOptions(const TriangleMesh& mesh,
                                          const FitOptions& options,
                                          int max_control_points);

// Whether `fit` missed its target with a round that folded.
bool MissedFolded(const FitResult& fit);

// Whether `first`, FitSphericalSpline's first fit of `mesh` with `options`,
// is returned as it is (map_vertices asked for, or an input with at least
// retry_map_vertices vertices).
bool RunsNoFurtherFits(const TriangleMesh& mesh, const FitOptions& options);

// The further fits of `mesh` after `first` (above), run by `fit`; the fit to
// return, with the seconds of all of them and, when it misses, what the
// others did in its shortfall. The result is the same for any thread count.
// `split_fit`, when given, runs the fit on the split input instead of `fit`.
FitResult FitAgain(const TriangleMesh& mesh, const FitOptions& options,
                   FitResult first, const FitRunner& fit,
                   const FitRunner* split_fit = nullptr);

}  // namespace sdcb

#endif  // SDCB_CORE_FIT_RETRY_STRATEGY_H_
