// Long scenarios of the fit's rounds on CGAL's meshes: each runs a whole
// adaptive fit to a tight target (10 to 40 s of CPU each), too long for the
// test command (scripts/test.sh), and checks the same properties as the
// fitting tests (tests/io/fit_on_cgal_meshes_test.cpp). Each fit prints its
// rounds, control points, errors and seconds. Built and registered (ctest
// label `long`) only with -DSDCB_LONG_TESTS=ON; run when the fitter changes:
//   cmake -S . -B build -DSDCB_LONG_TESTS=ON
//   cmake --build build -j2 --target sdcb_long_tests
//   ctest --test-dir build -L long --output-on-failure
// or build/tests/sdcb_long_tests [--gtest_filter=FitScenario.NAME].
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "sdcb/core/fit/spline_fitter.h"
#include "testing/cgal_test_mesh.h"
#include "testing/honest_fit_errors.h"

namespace sdcb {
namespace {

using testing::ExpectHonestSurfaceErrors;
using testing::ExpectHonestVertexErrors;
using testing::ReadCgalMesh;

// FitSphericalSpline, printing the fit's numbers and wall seconds.
StatusOr<FitResult> TimedFit(const std::string& name, const TriangleMesh& mesh,
                             const FitOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  StatusOr<FitResult> fit = FitSphericalSpline(mesh, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  if (!fit.ok()) return fit;
  const FitStatistics& s = fit->model.statistics;
  std::printf(
      "%s at %g %%: %zu rounds, %d control points, rms %.4f %%, max %.4f %%, "
      "folded %.4f %%, %s, %.1f s\n",
      name.c_str(), options.rmse_percent, s.rounds.size(),
      s.final_result.control_points, s.final_result.rmse_percent,
      s.final_result.max_error_percent, s.final_result.folded_area_percent,
      fit->reached_target() ? "reached" : "not reached", seconds);
  return fit;
}

// The 8-vertex beam fitted smooth (its corners' clusters would keep it in
// one round), K = 100: its rounds bound the mesh -> surface distance by the
// parametric residual at the rows of the data term, which its corners keep
// above the target in round 4 (0.108 % rms, where the surface is within
// 0.057 %). The round's first-order estimate (the residuals along the
// mesh's normals, 0.072 %) meets the target, so that round is measured
// densely (and misses the Hausdorff target there: 1.29 %); the fit ends when
// a round passes (round 6: 0.032 %, Hausdorff 0.89 %), and brute force at
// random surface points agrees with what it reports.
TEST(FitScenario, AFirstOrderEstimateSendsARoundToTheDenseMeasurement) {
  const TriangleMesh mesh = ReadCgalMesh("beam.off");
  FitOptions options;
  options.rmse_percent = 0.1;
  options.knots_per_round = 100;  // the paper's K, which these rounds follow
  options.keep_features = false;  // kept, the beam takes one round of clusters
  auto fit = TimedFit("beam.off", mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  const FitStatistics& s = fit->model.statistics;
  ASSERT_EQ(fit->round_details.size(), s.rounds.size());
  int sent_by_the_estimate = 0;
  for (size_t r = 0; r < s.rounds.size(); ++r) {
    const RoundDetails& d = fit->round_details[r];
    // Measured densely exactly when the bound or the estimate met the
    // target (no round of the beam folds).
    EXPECT_EQ(s.rounds[r].folded_area_percent, 0.0);
    EXPECT_EQ(d.closest_points,
              std::min(d.round_rmse_percent, d.estimated_rmse_percent) <= 0.1)
        << "round " << r;
    if (d.closest_points && d.round_rmse_percent > 0.1) {
      ++sent_by_the_estimate;
      EXPECT_LE(d.estimated_rmse_percent, 0.1);
      EXPECT_GT(d.mesh_samples, mesh.num_vertices());
      EXPECT_GE(d.mesh_to_surface_max_bound_percent, 0.0);
    }
  }
  EXPECT_GE(sent_by_the_estimate, 1);
  EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
  EXPECT_TRUE(fit->shortfall.empty());
  EXPECT_LE(s.final_result.rmse_percent, 0.1);
  EXPECT_LE(s.final_result.max_error_percent, 1.0);
  EXPECT_EQ(s.final_result.folded_area_percent, 0.0);
  // The beam's error is at its edges and corners, few of the random points:
  // 3,000 of them estimate its rms 1.6 times too high (30,000: 1.05 times;
  // 3 million: 0.0242 % against the lattice's 0.0240 %).
  ExpectHonestSurfaceErrors(mesh, *fit, 30000);
}

// fandisk_large at 0.05 % (no Hausdorff limit) in three rounds of K = 100:
// the last round's own rms (0.060 %) and its estimate (0.056 %) both miss the
// target, so it is not measured densely and the fit stops at the round
// limit. The returned surface, measured densely as a reached one is
// (0.046 %), meets the target: the fit says it reached it, and brute force
// agrees with the report.
TEST(FitScenario, AFitThatPassesTheFinalMeasurementHasReached) {
  const TriangleMesh mesh = ReadCgalMesh("fandisk_large.off");
  FitOptions options;
  options.rmse_percent = 0.05;
  options.max_error_percent = -1;
  options.max_rounds = 3;
  options.knots_per_round = 100;  // the paper's K, which these rounds follow
  auto fit = TimedFit("fandisk_large.off", mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  const FitStatistics& s = fit->model.statistics;
  ASSERT_EQ(s.rounds.size(), 3u);
  const RoundDetails& last = fit->round_details.back();
  EXPECT_FALSE(last.closest_points);
  EXPECT_GT(std::min(last.round_rmse_percent, last.estimated_rmse_percent),
            0.05);
  EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
  EXPECT_TRUE(fit->shortfall.empty());
  EXPECT_LE(s.final_result.rmse_percent, 0.05);
  EXPECT_EQ(s.final_result.folded_area_percent, 0.0);
  ExpectHonestSurfaceErrors(mesh, *fit, 2000);
}

// The bear (13,826 vertices) has far more vertices than its rounds have
// control points: every round's data term (more than eight vertices per
// control point) is thinned to the knots' density (about 12 rows per control
// point kept, well under half of the full quadrature), and the fit still
// reaches its target with errors that brute force confirms, the paper's vertex
// measure recomputed at every vertex.
TEST(FitScenario, ADenseMeshIsFittedOnRowsTiedToItsKnots) {
  const TriangleMesh mesh = ReadCgalMesh("bear.off");
  FitOptions options;
  options.rmse_percent = 0.1;
  auto fit = TimedFit("bear.off", mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
  const FitStatistics& s = fit->model.statistics;
  for (size_t r = 0; r < s.rounds.size(); ++r) {
    const RoundDetails& d = fit->round_details[r];
    EXPECT_LT(d.data_samples, d.unthinned_samples / 2) << "round " << r;
    EXPECT_LE(d.data_samples, 16 * s.rounds[r].control_points) << "round " << r;
    EXPECT_GE(d.unthinned_samples, mesh.num_vertices()) << "round " << r;
  }
  EXPECT_EQ(s.options.thinned_cells_per_spacing, 4.0);
  EXPECT_LE(s.final_result.rmse_percent, 0.1);
  EXPECT_EQ(s.final_result.folded_area_percent, 0.0);
  ExpectHonestVertexErrors(mesh, *fit);
  ExpectHonestSurfaceErrors(mesh, *fit, 2000);
}

// The cow at 0.3 % (K = 100) meets the rms in round 1 but folds (0.62 % of
// its area by the round's measurement). The rounds that place knots only at the
// folds (25 each) give way to an ordinary round (100) when two of them have not
// halved the folded area, and the fit ends once five of them have run and
// the surface still folds. Each round's kind is checked against the rule
// replayed over the rounds' statistics.
TEST(FitScenario, FoldRoundsGiveWayWhenTheFoldsDoNotShrink) {
  FitOptions options;
  options.rmse_percent = 0.3;
  options.knots_per_round = 100;  // the paper's K, which these rounds follow
  auto fit = TimedFit("cow.off", ReadCgalMesh("cow.off"), options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  const std::vector<RoundStatistics>& rounds = fit->model.statistics.rounds;
  int fold_rounds = 0, in_a_row = 0, ordinary_after_folds = 0;
  double began = 0;
  size_t expected_end = rounds.size();
  for (size_t r = 0; r < rounds.size(); ++r) {
    const bool only_folds =
        rounds[r].rmse_percent <= 0.3 && rounds[r].folded_area_percent > 0;
    if (only_folds && in_a_row == 0) began = rounds[r].folded_area_percent;
    if (only_folds && fold_rounds >= options.max_fold_rounds) {
      expected_end = r;
      break;
    }
    const bool stay =
        in_a_row >= 2 && rounds[r].folded_area_percent > 0.5 * began;
    const bool next_folds = only_folds && !stay;
    if (r + 1 < rounds.size()) {
      EXPECT_EQ(rounds[r + 1].knots - rounds[r].knots, next_folds ? 25 : 100)
          << "round " << r + 1;
    }
    if (next_folds) {
      ++fold_rounds;
      ++in_a_row;
    } else {
      ordinary_after_folds += fold_rounds > 0 && r + 1 < rounds.size();
      in_a_row = 0;
    }
  }
  EXPECT_EQ(rounds.size() - 1, expected_end);
  EXPECT_EQ(fold_rounds, options.max_fold_rounds);
  EXPECT_GE(ordinary_after_folds, 1);
  EXPECT_FALSE(fit->reached_target());
  EXPECT_NE(fit->shortfall.find("folds"), std::string::npos);
}

// The triceratops at 0.1 %: the rounds that meet the rms fold along its sharp
// steps (about 0.01 % of the area at the final measurement's lattice); their
// folds are repaired round after round (core/fit/fold_repair.h), and the fit
// reaches the target with nothing folded (as in every nearby run, --lambda
// 0.998 to 1.002; homer's folds between its fingers are removed in some runs
// only, docs/FITTING.md).
TEST(FitScenario, CreaseFoldsAreRepairedRoundAfterRound) {
  const TriangleMesh mesh = ReadCgalMesh("triceratops.off");
  FitOptions options;
  options.rmse_percent = 0.1;
  auto fit = TimedFit("triceratops.off", mesh, options);
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  EXPECT_TRUE(fit->reached_target()) << fit->shortfall;
  EXPECT_EQ(fit->model.statistics.final_result.folded_area_percent, 0.0);
  int tried = 0, repaired = 0;
  for (const RoundDetails& d : fit->round_details) {
    tried += d.folded_before_repair_percent > 0;
    repaired += d.fold_repaired;
  }
  EXPECT_GE(tried, 3);
  EXPECT_GE(repaired, 2);
  EXPECT_TRUE(fit->round_details.back().fold_repaired);
  ExpectHonestVertexErrors(mesh, *fit);
  ExpectHonestSurfaceErrors(mesh, *fit, 2000);
  EXPECT_EQ(testing::BruteForceFoldedPoints(mesh, *fit, 5000), 0);
}

}  // namespace
}  // namespace sdcb
