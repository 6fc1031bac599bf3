#include "sdcb/core/fit/retry_strategy.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <string>
#include <utility>

#include "sdcb/core/fit/fallback_round.h"
#include "sdcb/core/fit/fit_mesh.h"
#include "sdcb/core/fit/fit_progress.h"
#include "sdcb/core/mesh/self_intersections.h"

namespace sdcb {
namespace {

// Whether the mesh passes through itself (FindSelfIntersections), on at
// most `threads` threads (0: as many as the caller's context allows). A
// surface that follows such a mesh folds where it does, split or not.
bool IntersectsItself(const TriangleMesh& mesh, int threads) {
  // (`automatic` is copied: binding a reference to it needs a definition
  // this TBB version does not export.)
  const int automatic = tbb::task_arena::automatic;
  tbb::task_arena arena(threads > 0 ? threads : automatic);
  return arena.execute([&] {
    const StatusOr<SelfIntersectionReport> report = FindSelfIntersections(mesh);
    return report.ok() && report->checked && report->intersecting_pairs > 0;
  });
}

bool AnyRoundFolded(const FitStatistics& stats) {
  for (const RoundStatistics& r : stats.rounds) {
    if (r.folded_area_percent > 0) return true;
  }
  return false;
}

std::string Summary(const FitResult& fit) {
  const RoundStatistics& r = fit.model.statistics.final_result;
  return std::to_string(r.control_points) + " control points, rms " +
         ShortNumber(r.rmse_percent) + " %, folded " +
         ShortNumber(r.folded_area_percent) + " % of its area";
}

// `options` whose progress reports carry `retry`.
FitOptions Retry(const FitOptions& options, const std::string& retry) {
  FitOptions again = options;
  if (options.progress) {
    again.progress = [&options, retry](const FitProgress& p) {
      FitProgress labelled = p;
      labelled.retry = retry;
      options.progress(labelled);
    };
  }
  return again;
}

// The fit on the split input (FitOptions::retry_map_vertices) when `first`
// calls for it, and the better of the two.
FitResult FitAgainSplit(const TriangleMesh& mesh, const FitOptions& options,
                        FitResult first, bool intersects_itself,
                        const FitRunner& fit) {
  // A fit that reached the target smooth with more control points than the
  // input has vertices (its knots about as dense as the input's triangles:
  // the spline follows the map's jumps between them, as on a CAD solid's
  // few large triangles whose edges it rounds); a fit that missed with a
  // folded round, on a mesh that does not pass through itself.
  const RoundStatistics& returned = first.model.statistics.final_result;
  const bool dense_knots = first.reached_target() && !first.features_kept &&
                           returned.control_points > mesh.num_vertices();
  const bool folded = MissedFolded(first) && !intersects_itself;
  if (!dense_knots && !folded) return first;
  const std::optional<FitOptions> again =
      SplitFitOptions(mesh, options, returned.control_points);
  if (!again) return first;
  StatusOr<FitResult> second = fit(*again);
  if (!second.ok()) return first;
  // Of two that reach, the one with fewer control points.
  const bool take_second =
      first.reached_target()
          ? second->reached_target() &&
                second->model.statistics.final_result.control_points <
                    returned.control_points
          : ReplacesMissedFit(*second, first, options);
  FitResult& kept = take_second ? *second : first;
  const FitResult& other = take_second ? first : *second;
  kept.split_retry_run = true;
  kept.split_retry_returned = take_second;
  AddSeconds(other, &kept);
  if (!take_second && !first.reached_target()) {
    kept.shortfall += "; a second fit on the input split to " +
                      std::to_string(second->map_vertices) +
                      " vertices did no better (" + Summary(*second) + ")";
  }
  return std::move(kept);
}

// Thin parts: fits with the map's area term weaker while `best` misses and
// folds; on the split input when the fit to return has more control points
// than the input has vertices. The better of them and `best`.
FitResult FitWithSmallerLambdas(const TriangleMesh& mesh,
                                const FitOptions& options, FitResult best,
                                bool intersects_itself, const FitRunner& fit) {
  std::string tried;
  for (double factor : options.retry_lambda_factors) {
    if (!MissedFolded(best) || intersects_itself) break;
    const double lambda = options.lambda * factor;
    const bool split = best.model.statistics.final_result.control_points >
                           mesh.num_vertices() &&
                       SplitForMap(mesh, options.retry_map_vertices);
    FitOptions lower = Retry(options, std::string(split ? "split, " : "") +
                                          "lambda " + ShortNumber(lambda));
    lower.lambda = lambda;
    if (split) {
      lower.map_vertices = options.retry_map_vertices;
      lower.keep_features = false;
    }
    StatusOr<FitResult> retry = fit(lower);
    if (!retry.ok()) break;
    const bool take = ReplacesMissedFit(*retry, best, options);
    FitResult& kept = take ? *retry : best;
    FitResult& other = take ? best : *retry;
    kept.lambda_retries_run = best.lambda_retries_run + 1;
    kept.split_retry_run = best.split_retry_run;
    kept.split_retry_returned = take ? false : best.split_retry_returned;
    AddSeconds(other, &kept);
    if (take && !kept.reached_target()) {
      kept.shortfall += "; this is a fit with lambda " + ShortNumber(lambda) +
                        ", folded less than the one before it (" +
                        Summary(other) + ")";
    } else if (!take) {
      tried += (tried.empty() ? "" : "; ") + std::string("lambda ") +
               ShortNumber(lambda) + ": " + Summary(*retry);
    }
    if (take) best = std::move(*retry);
  }
  if (!tried.empty() && !best.reached_target()) {
    best.shortfall +=
        "; fits with a smaller lambda did no better (" + tried + ")";
  }
  return best;
}

}  // namespace

void AddSeconds(const FitResult& other, FitResult* kept) {
  AddRoundStages(other.timings, &kept->timings);
  kept->timings.parameterization += other.timings.parameterization;
  kept->timings.total += other.timings.total;
}

std::optional<FitOptions> SplitFitOptions(const TriangleMesh& mesh,
                                          const FitOptions& options,
                                          int max_control_points) {
  if (!SplitForMap(mesh, options.retry_map_vertices)) return std::nullopt;
  FitOptions again = Retry(options, "split");
  again.map_vertices = options.retry_map_vertices;
  // Smooth: corners' clusters, had they been kept, would have ended the
  // first fit (and they are tried on the input's own triangles only).
  again.keep_features = false;
  again.max_control_points =
      std::min(options.max_control_points, max_control_points);
  return again;
}

bool ReplacesMissedFit(const FitResult& candidate, const FitResult& current,
                       const FitOptions& options) {
  if (candidate.reached_target()) return true;
  const RoundStatistics& a = candidate.model.statistics.final_result;
  const RoundStatistics& b = current.model.statistics.final_result;
  if (!options.fallback_accepts_folds && a.folded_area_percent > 0 &&
      b.folded_area_percent > 0) {
    return a.folded_area_percent < b.folded_area_percent;
  }
  return IsBetterFallback(a, b, options.fallback_accepts_folds);
}

bool MissedFolded(const FitResult& fit) {
  return !fit.reached_target() && AnyRoundFolded(fit.model.statistics);
}

bool RunsNoFurtherFits(const TriangleMesh& mesh, const FitOptions& options) {
  return options.map_vertices > 0 ||
         mesh.num_vertices() >= options.retry_map_vertices;
}

FitResult FitAgain(const TriangleMesh& mesh, const FitOptions& options,
                   FitResult first, const FitRunner& fit,
                   const FitRunner* split_fit) {
  const bool intersects_itself =
      MissedFolded(first) && IntersectsItself(mesh, options.threads);
  FitResult best =
      FitAgainSplit(mesh, options, std::move(first), intersects_itself,
                    split_fit != nullptr ? *split_fit : fit);
  return FitWithSmallerLambdas(mesh, options, std::move(best),
                               intersects_itself, fit);
}

}  // namespace sdcb
