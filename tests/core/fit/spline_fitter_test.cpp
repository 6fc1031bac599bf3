// The fitting driver (core/fit/spline_fitter.h) stepped round by round, and
// the rules it stops by (core/fit/stop_rule.h): the target reached only when
// the rms and the Hausdorff distance are within their targets and nothing
// folds; max_rounds, the control-point cap, fold rounds and a stalled error
// end a fit that misses; and which of two fits a retry returns
// (core/fit/retry_strategy.h).
#include "sdcb/core/fit/spline_fitter.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "sdcb/core/fit/retry_strategy.h"
#include "sdcb/core/fit/stop_rule.h"
#include "sdcb/core/mesh/icosphere.h"

namespace sdcb {
namespace {

RoundStatistics Round(int round, int knots, double rms, double max_error,
                      double folded) {
  RoundStatistics r;
  r.round = round;
  r.knots = knots;
  r.rmse_percent = rms;
  r.max_error_percent = max_error;
  r.folded_area_percent = folded;
  return r;
}

TEST(TargetTest, ReachedOnlyWhenRmsAndHausdorffAreWithinAndNothingFolds) {
  const FitTarget target{0.1, 1.0};
  struct Case {
    double rms, max_error, folded;
    bool rms_met, max_met, unfolded;
  };
  const Case cases[] = {
      {0.1, 1.0, 0.0, true, true, true},          // both on the target
      {0.05, 0.5, 0.0, true, true, true},         // both below
      {0.1000001, 0.5, 0.0, false, true, true},   // rms just above
      {0.05, 1.0000001, 0.0, true, false, true},  // Hausdorff just above
      {0.05, 0.5, 1e-9, true, true, false},       // the least fold
      {0.2, 2.0, 0.3, false, false, false},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(::testing::Message()
                 << c.rms << " " << c.max_error << " " << c.folded);
    const TargetCheck check =
        CompareWithTarget(target, c.rms, c.max_error, c.folded);
    EXPECT_EQ(check.rms, c.rms_met);
    EXPECT_EQ(check.max_error, c.max_met);
    EXPECT_EQ(check.unfolded, c.unfolded);
    EXPECT_EQ(check.reached(), c.rms_met && c.max_met && c.unfolded);
    EXPECT_EQ(
        CompareWithTarget(target, Round(0, 10, c.rms, c.max_error, c.folded))
            .reached(),
        check.reached());
  }
}

// An open part's boundary distance has a target of its own, 0.4 of the
// Hausdorff target; a closed part (boundary -1) has none.
TEST(TargetTest, AnOpenPartReachesOnlyWithItsBoundaryWithinItsTarget) {
  FitOptions options;
  options.rmse_percent = 0.1;
  const FitTarget target = FitTarget::Of(options);
  EXPECT_DOUBLE_EQ(target.boundary_percent, 0.4);
  EXPECT_TRUE(CompareWithTarget(target, 0.1, 1.0, 0.0, 0.4).reached());
  const TargetCheck above = CompareWithTarget(target, 0.1, 1.0, 0.0, 0.4001);
  EXPECT_TRUE(above.rms && above.max_error && above.unfolded);
  EXPECT_FALSE(above.boundary);
  EXPECT_FALSE(above.reached());
  EXPECT_TRUE(CompareWithTarget(target, 0.1, 1.0, 0.0, -1.0).reached());
  RoundStatistics open = Round(0, 10, 0.05, 0.5, 0.0);
  open.boundary_error_percent = 0.5;
  EXPECT_FALSE(CompareWithTarget(target, open).reached());
  options.max_error_percent = -1;  // no Hausdorff target: no boundary one
  EXPECT_TRUE(
      CompareWithTarget(FitTarget::Of(options), 0.1, 9.0, 0.0, 9.0).reached());
}

TEST(TargetTest, WithoutAHausdorffTargetAnyHausdorffDistanceIsWithin) {
  const FitTarget target{0.1, -1.0};
  EXPECT_TRUE(CompareWithTarget(target, 0.1, 1e9, 0.0).reached());
  EXPECT_FALSE(CompareWithTarget(target, 0.11, 0.0, 0.0).reached());
}

TEST(TargetTest, TheOptionsTargetIsTheirRmsAndMaxErrorTarget) {
  FitOptions options;
  options.rmse_percent = 0.07;
  options.max_error_percent = 0;  // ten times the rms
  FitTarget target = FitTarget::Of(options);
  EXPECT_EQ(target.rmse_percent, 0.07);
  EXPECT_EQ(target.max_error_percent, MaxErrorTarget(options));
  EXPECT_DOUBLE_EQ(target.max_error_percent, 0.7);
  options.max_error_percent = -1;
  EXPECT_LT(FitTarget::Of(options).max_error_percent, 0);
}

FitOptions StopOptions() {
  FitOptions options;
  options.rmse_percent = 0.1;
  options.max_error_percent = 1.0;
  options.max_rounds = 8;
  options.max_fold_rounds = 2;
  options.max_control_points = 500;
  options.knots_per_round = 40;
  options.knots_growth = 0.5;
  return options;
}

TEST(StopRuleTest, AFitThatMissesStopsAtMaxRounds) {
  FitOptions options = StopOptions();
  options.max_rounds = 3;
  StopRule stop(options);
  std::vector<RoundStatistics> rounds;
  int estimated = 0;
  for (int r = 0; r < 3; ++r) {
    // The rms halves every round, still above the target after three.
    rounds.push_back(Round(r, 40 * (r + 1), 0.8 / (1 << r), 2.0, 0.0));
    const std::optional<std::string> why =
        stop.AfterMissedRound(rounds, &estimated);
    if (r < 2) {
      EXPECT_FALSE(why) << r << ": " << *why;
    } else {
      ASSERT_TRUE(why);
      EXPECT_EQ(*why, "the target was not reached within 3 rounds");
    }
    EXPECT_FALSE(stop.fold_round());
  }
  // After two rounds the rate says: 0.4 -> 0.1 at halving per round.
  EXPECT_EQ(estimated, 3);
}

TEST(StopRuleTest, RoundsThatMeetTheRmsButFoldBecomeFoldRoundsAFewTimes) {
  StopRule stop(StopOptions());  // max_fold_rounds 2
  std::vector<RoundStatistics> rounds;
  int estimated = 0;
  rounds.push_back(Round(0, 40, 0.3, 2.0, 0.0));
  EXPECT_FALSE(stop.AfterMissedRound(rounds, &estimated));
  EXPECT_FALSE(stop.fold_round());
  // Met the rms, folded: the next rounds only remove folds (the folds
  // shrinking, so that they do not give way to an ordinary round).
  const double folds[] = {0.04, 0.01, 0.004};
  for (int r = 1; r <= 3; ++r) {
    rounds.push_back(Round(r, 40 + 10 * r, 0.09, 0.5, folds[r - 1]));
    const std::optional<std::string> why =
        stop.AfterMissedRound(rounds, &estimated);
    if (r <= 2) {
      EXPECT_FALSE(why) << r;
      EXPECT_TRUE(stop.fold_round()) << r;
    } else {
      ASSERT_TRUE(why);
      EXPECT_EQ(why->find("the surface still folds"), 0u) << *why;
    }
  }
}

TEST(StopRuleTest, AFoldRoundKeepsTheFoldRoundsKnotCount) {
  FitOptions options = StopOptions();
  StopRule stop(options);
  std::vector<RoundStatistics> rounds;
  // Round 0: knots_per_round (initial_knots 0).
  EXPECT_EQ(stop.RoundKnots(rounds, 0), 40);
  int estimated = 0;
  rounds.push_back(Round(0, 40, 0.3, 2.0, 0.0));
  EXPECT_FALSE(stop.AfterMissedRound(rounds, &estimated));
  // Growth: max(40, 0.5 x 200).
  EXPECT_EQ(stop.RoundKnots(rounds, 200), 100);
  rounds.push_back(Round(1, 80, 0.09, 0.5, 0.01));
  EXPECT_FALSE(stop.AfterMissedRound(rounds, &estimated));
  ASSERT_TRUE(stop.fold_round());
  EXPECT_EQ(stop.RoundKnots(rounds, 200), kMinFoldKnots);  // 40 / 4 = 10
  options.initial_knots = 123;
  EXPECT_EQ(StopRule(options).RoundKnots({}, 0), 123);
}

TEST(StopRuleTest, TheControlPointCapStopsEveryRoundButTheFirst) {
  const StopRule stop(StopOptions());  // cap 500
  EXPECT_FALSE(stop.ControlPointLimit(0, 100000));
  EXPECT_FALSE(stop.ControlPointLimit(3, 500));
  const std::optional<std::string> why = stop.ControlPointLimit(3, 501);
  ASSERT_TRUE(why);
  EXPECT_EQ(*why, "the next round would exceed 500 control points");
}

TEST(StopRuleTest, AnErrorThatStopsFallingStopsTheFitAfterSixRounds) {
  StopRule stop(StopOptions());
  std::vector<RoundStatistics> rounds;
  int estimated = 0;
  for (int r = 0; r < 6; ++r) {
    rounds.push_back(Round(r, 40 * (r + 1), 0.5, 2.0, 0.0));  // flat
    const std::optional<std::string> why =
        stop.AfterMissedRound(rounds, &estimated);
    if (r < 5) {
      EXPECT_FALSE(why) << r;
    } else {
      ASSERT_TRUE(why);
      EXPECT_EQ(*why, "the error stopped falling");
    }
  }
}

TEST(StopRuleTest, TheRateOfDecayGivesTheRoundsStillNeeded) {
  const FitTarget target{0.06, -1.0};
  EXPECT_EQ(RoundsToTarget({Round(0, 40, 0.8, 1, 0)}, target), -1);
  // Halving per round: 0.2 -> 0.06 takes log(0.3) / log(0.5) = 1.7 rounds.
  EXPECT_EQ(RoundsToTarget({Round(0, 40, 0.8, 1, 0), Round(1, 80, 0.4, 1, 0),
                            Round(2, 120, 0.2, 1, 0)},
                           target),
            2);
  // Not falling.
  EXPECT_EQ(RoundsToTarget({Round(0, 40, 0.4, 1, 0), Round(1, 80, 0.4, 1, 0)},
                           target),
            -1);
  // Met: at least one round (the count is at least 1 once it can be said).
  EXPECT_EQ(RoundsToTarget({Round(0, 40, 0.4, 1, 0), Round(1, 80, 0.05, 1, 0)},
                           target),
            1);
}

TEST(StopRuleTest, TheLastRoundIsSizedByThePowerLawToTheTarget) {
  const FitTarget target{0.1, 1.0};
  // rms ~ 1 / knots: 0.1 at 400 knots; the round adds 0.7 of the 200 more.
  const std::vector<RoundStatistics> rounds = {Round(0, 100, 0.4, 0.5, 0),
                                               Round(1, 200, 0.2, 0.5, 0)};
  EXPECT_EQ(KnotsToTarget(rounds, target, 300), 140);
  EXPECT_EQ(KnotsToTarget(rounds, target, 100), 100);  // planned is fewer
  // Not sized: a folded round, or one above the Hausdorff target.
  std::vector<RoundStatistics> folded = rounds;
  folded[1].folded_area_percent = 0.01;
  EXPECT_EQ(KnotsToTarget(folded, target, 300), 300);
  std::vector<RoundStatistics> far = rounds;
  far[1].max_error_percent = 1.5;
  EXPECT_EQ(KnotsToTarget(far, target, 300), 300);
  // An open part's round above the Hausdorff target is sized, unless it is
  // above its boundary target too.
  const FitTarget open_target{0.1, 1.0, 0.4};
  std::vector<RoundStatistics> open = far;
  for (RoundStatistics& r : open) r.boundary_error_percent = 0.3;
  EXPECT_EQ(KnotsToTarget(open, open_target, 300), 140);
  open[1].boundary_error_percent = 0.5;
  EXPECT_EQ(KnotsToTarget(open, open_target, 300), 300);
}

FitResult MissedFit(double rms, double folded) {
  FitResult fit;
  fit.model.statistics.final_result = Round(0, 10, rms, 1, folded);
  fit.model.statistics.rounds = {fit.model.statistics.final_result};
  return fit;
}

TEST(RetryStrategyTest, AFurtherFitReplacesAMissedOneInTheFallbackOrder) {
  FitOptions options;
  FitResult reached = MissedFit(0.5, 0.1);
  reached.model.statistics.reached_target = true;
  EXPECT_TRUE(ReplacesMissedFit(reached, MissedFit(0.01, 0), options));
  // Of two folded fits, the one folded less, whatever their rms.
  EXPECT_TRUE(
      ReplacesMissedFit(MissedFit(0.5, 0.1), MissedFit(0.1, 0.2), options));
  EXPECT_FALSE(
      ReplacesMissedFit(MissedFit(0.1, 0.2), MissedFit(0.5, 0.1), options));
  // Unfolded before folded, then the smaller rms.
  EXPECT_TRUE(
      ReplacesMissedFit(MissedFit(0.5, 0), MissedFit(0.1, 0.2), options));
  EXPECT_TRUE(ReplacesMissedFit(MissedFit(0.1, 0), MissedFit(0.2, 0), options));
  EXPECT_FALSE(
      ReplacesMissedFit(MissedFit(0.2, 0), MissedFit(0.1, 0), options));
  options.fallback_accepts_folds = true;
  EXPECT_TRUE(
      ReplacesMissedFit(MissedFit(0.1, 0.2), MissedFit(0.5, 0), options));
  EXPECT_TRUE(MissedFolded(MissedFit(0.1, 0.2)));
  EXPECT_FALSE(MissedFolded(MissedFit(0.1, 0)));
}

// A sphere of 162 vertices, fitted with few knots and no further fits.
FitOptions TinyFitOptions() {
  FitOptions options;
  options.rmse_percent = 0.5;
  options.knots_per_round = 20;
  options.max_rounds = 4;
  options.retry_map_vertices = 0;  // FitSphericalSpline's first fit only
  options.final_surface_samples = 4000;
  options.final_mesh_samples = 4000;
  options.threads = 2;
  return options;
}

TEST(SplineFitterTest, SteppedRoundByRoundItGivesFitSphericalSplinesModel) {
  const TriangleMesh sphere = MakeIcosphere(2);
  const FitOptions options = TinyFitOptions();
  StatusOr<SplineFitter> fitter = SplineFitter::Create(sphere, options);
  ASSERT_TRUE(fitter.ok()) << fitter.status().message();
  EXPECT_EQ(fitter->rounds(), 0);
  EXPECT_FALSE(fitter->finished());
  int steps = 0;
  while (!fitter->finished()) {
    ASSERT_TRUE(fitter->AddRound().ok());
    ++steps;
    ASSERT_LE(steps, options.max_rounds);
    EXPECT_EQ(fitter->rounds(), steps);
    EXPECT_EQ(fitter->model().statistics.rounds.size(),
              static_cast<size_t>(steps));
  }
  EXPECT_GE(steps, 2);  // round 0 alone misses the target
  EXPECT_EQ(fitter->AddRound().code(), StatusCode::kInvalidArgument);
  const FitResult stepped = fitter->TakeResult();
  EXPECT_TRUE(stepped.reached_target()) << stepped.shortfall;
  EXPECT_TRUE(stepped.shortfall.empty());
  EXPECT_EQ(stepped.round_details.size(), static_cast<size_t>(steps));
  const RoundStatistics& last = stepped.model.statistics.final_result;
  EXPECT_EQ(last.round, steps - 1);
  EXPECT_TRUE(CompareWithTarget(FitTarget::Of(options), last).reached());

  StatusOr<FitResult> once = FitSphericalSpline(sphere, options);
  ASSERT_TRUE(once.ok()) << once.status().message();
  EXPECT_EQ(once->model.statistics.rounds.size(), static_cast<size_t>(steps));
  EXPECT_EQ(once->model.knots, stepped.model.knots);
  EXPECT_EQ(once->model.control_points, stepped.model.control_points);
  EXPECT_EQ(once->model.statistics.final_result.rmse_percent,
            last.rmse_percent);
  EXPECT_EQ(once->vertex_errors_percent, stepped.vertex_errors_percent);
  EXPECT_FALSE(once->split_retry_run);
  EXPECT_EQ(once->lambda_retries_run, 0);
}

// Paused before every round after round 0 (PauseAbove(1)) and resumed each
// time, a fit places each held-back round again the same way: the model is
// the one never paused. AddRound while paused is refused.
TEST(SplineFitterTest, PausedAndResumedItGivesTheModelNeverPaused) {
  const TriangleMesh sphere = MakeIcosphere(2);
  const FitOptions options = TinyFitOptions();
  StatusOr<SplineFitter> fitter = SplineFitter::Create(sphere, options);
  ASSERT_TRUE(fitter.ok()) << fitter.status().message();
  int pauses = 0;
  while (!fitter->finished()) {
    fitter->PauseAbove(1);
    ASSERT_TRUE(fitter->AddRound().ok());
    if (!fitter->paused()) continue;
    ++pauses;
    ASSERT_LE(pauses, options.max_rounds);
    const int rounds = fitter->rounds();
    EXPECT_EQ(fitter->AddRound().code(), StatusCode::kInvalidArgument);
    fitter->PauseAbove(0);
    EXPECT_FALSE(fitter->paused());
    ASSERT_TRUE(fitter->AddRound().ok());
    EXPECT_EQ(fitter->rounds(), rounds + 1);
  }
  EXPECT_GE(pauses, 1);
  const FitResult paused = fitter->TakeResult();
  StatusOr<FitResult> once = FitSphericalSpline(sphere, options);
  ASSERT_TRUE(once.ok()) << once.status().message();
  EXPECT_EQ(once->model.knots, paused.model.knots);
  EXPECT_EQ(once->model.control_points, paused.model.control_points);
  EXPECT_EQ(once->vertex_errors_percent, paused.vertex_errors_percent);
}

// A fit of the sphere that misses, stepped by two AddRound calls: not
// finished after the first, finished after the second with `rounds`
// rounds; its result.
FitResult StepTwice(const FitOptions& options, int rounds) {
  StatusOr<SplineFitter> fitter =
      SplineFitter::Create(MakeIcosphere(2), options);
  EXPECT_TRUE(fitter.ok()) << fitter.status().message();
  if (!fitter.ok()) return FitResult();
  EXPECT_TRUE(fitter->AddRound().ok());
  EXPECT_FALSE(fitter->finished());
  EXPECT_TRUE(fitter->AddRound().ok());
  EXPECT_TRUE(fitter->finished());
  EXPECT_EQ(fitter->rounds(), rounds);
  if (!fitter->finished()) return FitResult();
  const FitResult result = fitter->TakeResult();
  EXPECT_FALSE(result.reached_target());
  return result;
}

TEST(SplineFitterTest, AFitThatCannotReachItsTargetStopsAtMaxRounds) {
  FitOptions options = TinyFitOptions();
  options.rmse_percent = 1e-6;
  options.max_error_percent = -1;
  options.max_rounds = 2;
  const FitResult result = StepTwice(options, 2);
  EXPECT_EQ(result.shortfall.find("the target was not reached within 2 rounds"),
            0u)
      << result.shortfall;
}

TEST(SplineFitterTest, ARoundAboveTheControlPointCapIsNotAdded) {
  FitOptions options = TinyFitOptions();
  options.rmse_percent = 1e-6;
  options.max_control_points = 1;  // round 0 is added all the same
  const FitResult result = StepTwice(options, 1);
  EXPECT_EQ(
      result.shortfall.find("the next round would exceed 1 control points"), 0u)
      << result.shortfall;
}

}  // namespace
}  // namespace sdcb
