#include "sdcb/core/fit/fold_progress.h"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

namespace sdcb {
namespace {

// (knots, folded area in % of the surface) of each round of measured fits
// at 70 knots per round, `sdcb fit MESH --rmse 0.1 --json` without the rule.
using Rounds = std::vector<std::pair<int, double>>;

// The index of the round that stalls the fit, or -1.
int StallingRound(const Rounds& rounds) {
  FoldProgress progress;
  for (size_t i = 0; i < rounds.size(); ++i) {
    if (progress.Stalls(rounds[i].first, rounds[i].second)) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

// CGAL's diplodocus (it intersects itself): folds of 1.3 % to 2.7 % of its
// area from 210 knots to the control-point cap.
TEST(FoldProgressTest, FoldsThatGrowWithTheKnotsStall) {
  const Rounds diplodocus = {{70, 4.9912},   {140, 1.8247}, {210, 1.3216},
                             {280, 2.0556},  {350, 2.0246}, {437, 1.7723},
                             {546, 1.946},   {682, 2.1671}, {852, 2.5967},
                             {1065, 2.4718}, {1331, 2.6016}};
  EXPECT_EQ(StallingRound(diplodocus), 8);  // 852 >= 4 x 210 knots
  FoldProgress progress;
  for (int i = 0; i <= 8; ++i) {
    progress.Stalls(diplodocus[i].first, diplodocus[i].second);
  }
  EXPECT_EQ(progress.knots_at_least(), 210);
  EXPECT_DOUBLE_EQ(progress.least_folded_percent(), 1.3216);
}

// CGAL's armadillo refined to 1.66M vertices: its coarse rounds fold a
// little (0.022 % at 70 knots, 0.039 % at 280, four times as many), then
// fold rounds shrink the folds to 0.002 %. Small folds never stall a fit.
TEST(FoldProgressTest, SmallFoldsOfACoarseStartDoNotStall) {
  const Rounds armadillo = {{70, 0.0222},  {140, 0.0369}, {210, 0.1412},
                            {280, 0.0387}, {350, 0.0448}, {437, 0.0428},
                            {546, 0.0224}, {682, 0.0073}, {852, 0.0017},
                            {869, 0.0024}, {886, 0.0053}, {1107, 0.006}};
  EXPECT_EQ(StallingRound(armadillo), -1);
}

// Folds that shrink as knots are added never stall, however large; nor do
// rounds without folds, whatever came before.
TEST(FoldProgressTest, ShrinkingFoldsAndFoldFreeRoundsDoNotStall) {
  EXPECT_EQ(StallingRound(
                {{70, 4.0}, {140, 3.0}, {280, 2.0}, {560, 1.0}, {1120, 0.9}}),
            -1);
  EXPECT_EQ(StallingRound({{70, 1.0}, {280, 0.0}, {560, 0.0}, {1120, 0.0}}),
            -1);
  // As much as the least, at exactly four times its knots: stalls.
  EXPECT_EQ(StallingRound({{70, 1.0}, {140, 2.0}, {280, 1.0}}), 2);
  EXPECT_EQ(StallingRound({{70, 1.0}, {140, 2.0}, {279, 1.0}}), -1);
}

}  // namespace
}  // namespace sdcb
