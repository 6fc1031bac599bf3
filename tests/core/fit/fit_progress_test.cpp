// The progress fractions a fit reports (core/fit/fit_progress.h).
#include "sdcb/core/fit/fit_progress.h"

#include <gtest/gtest.h>

#include <vector>

namespace sdcb {
namespace {

TEST(FitProgressTest, TheParameterizationThenTheEstimatedRoundsShareTheFit) {
  std::vector<FitProgress> reports;
  ProgressReporter progress(
      [&reports](const FitProgress& p) { reports.push_back(p); });
  progress.Report(FitStage::kParameterization, 0, 0.5);
  progress.set_estimated_rounds(5);
  progress.StartRoundStage(FitStage::kKnotPlacement, 1);
  progress.StartRoundStage(FitStage::kSolve, 1);
  // More rounds than estimated: the round counts as the last.
  progress.StartRoundStage(FitStage::kMeasure, 7);
  progress.Report(FitStage::kDone, 8, 0);
  ASSERT_EQ(reports.size(), 5u);
  EXPECT_DOUBLE_EQ(reports[0].fraction, 0.5 * kParameterizationShare);
  EXPECT_DOUBLE_EQ(reports[1].fraction,
                   kParameterizationShare + (1 - kParameterizationShare) / 5);
  EXPECT_DOUBLE_EQ(
      reports[2].fraction,
      kParameterizationShare + (1 - kParameterizationShare) * 1.55 / 5);
  EXPECT_EQ(reports[2].stage, FitStage::kSolve);
  EXPECT_EQ(reports[2].round, 1);
  EXPECT_DOUBLE_EQ(
      reports[3].fraction,
      kParameterizationShare + (1 - kParameterizationShare) * 7.75 / 8);
  EXPECT_EQ(reports[4].fraction, 1.0);
}

TEST(FitProgressTest, WithoutACallbackNothingIsReported) {
  const ProgressReporter progress(nullptr);
  progress.Report(FitStage::kDone, 0, 0);  // does not call an empty function
}

}  // namespace
}  // namespace sdcb
