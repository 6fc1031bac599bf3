#include "sdcb/core/spline/delaunay_configurations.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "sdcb/core/sphere/perturbed_predicates.h"
#include "sdcb/core/spline/knot_hull.h"
#include "testing/brute_force_configurations.h"
#include "testing/random_knots.h"
#include "testing/special_knots.h"

namespace sdcb {
namespace {

using testing::ClusteredKnots;
using testing::CubeKnots;
using testing::GreatCirclePlusPoles;
using testing::IcosahedronKnots;
using testing::LatLongGrid;
using testing::UniformKnots;

int CountConfigurations(const DelaunayConfigurations& c) {
  int count = 0;
  for (const ConfigurationSet& s : c.sets)
    count += static_cast<int>(s.boundaries.size());
  return count;
}

// Compares with the brute-force oracle at every degree 0..5 the knot count
// allows.
void ExpectMatchesBruteForce(const Eigen::MatrixX3d& knots,
                             const std::string& label) {
  const int n = static_cast<int>(knots.rows());
  const int max_degree = std::min(5, n - 4);
  const auto oracle = testing::BruteForceConfigurationsUpTo(knots, max_degree);
  DelaunayConfigurationOptions options;
  for (int k = 0; k <= max_degree; ++k) {
    // The default and the locally verified variant must both match.
    for (const bool always_verify : {false, true}) {
      options.always_verify = always_verify;
      const auto result = ComputeDelaunayConfigurations(knots, k, options);
      ASSERT_TRUE(result.ok())
          << label << " k=" << k << ": " << result.status().message();
      EXPECT_EQ(result->degree, k);
      ASSERT_EQ(result->sets.size(), oracle[k].sets.size())
          << label << " k=" << k;
      for (size_t i = 0; i < oracle[k].sets.size(); ++i) {
        ASSERT_EQ(result->sets[i].knots, oracle[k].sets[i].knots)
            << label << " k=" << k;
        ASSERT_EQ(result->sets[i].boundaries, oracle[k].sets[i].boundaries)
            << label << " k=" << k;
      }
    }
  }
}

TEST(DelaunayConfigurationsTest, MatchesBruteForceOnUniformKnots) {
  for (int n : {10, 11, 17, 40, 100, 200}) {
    ExpectMatchesBruteForce(UniformKnots(n, 100 + n),
                            "uniform n=" + std::to_string(n));
  }
}

TEST(DelaunayConfigurationsTest, MatchesBruteForceOnClusteredKnots) {
  // 90 % of the knots in a 10-degree cap (the density-driven placement).
  for (int n : {12, 30, 80, 200}) {
    ExpectMatchesBruteForce(ClusteredKnots(n, 0.9, 10, 7 + n),
                            "clustered n=" + std::to_string(n));
  }
}

TEST(DelaunayConfigurationsTest, MatchesBruteForceOnManySmallSets) {
  // Small sets hit the rare cases: facets whose few knots are on the
  // origin's side, knots crowded into part of the sphere.
  for (unsigned seed = 0; seed < 60; ++seed) {
    const int n = 8 + static_cast<int>(seed % 23);
    Eigen::MatrixX3d knots;
    if (seed % 3 == 0) {
      knots = UniformKnots(n, seed);
    } else if (seed % 3 == 1) {
      knots = ClusteredKnots(n, 0.9, 10, seed);
    } else {
      knots = ClusteredKnots(n, 1.0, 20.0 + seed, seed);
    }
    ExpectMatchesBruteForce(knots, "seed " + std::to_string(seed));
  }
}

TEST(DelaunayConfigurationsTest,
     MatchesBruteForceWhenAllKnotsShareAHemisphere) {
  // No knot on one side of many great circles: the configurations do not
  // cover the sphere and searches end on great circles.
  ExpectMatchesBruteForce(ClusteredKnots(60, 1.0, 10, 3), "one 10-degree cap");
  ExpectMatchesBruteForce(ClusteredKnots(80, 1.0, 80, 4), "one 80-degree cap");
  ExpectMatchesBruteForce(ClusteredKnots(50, 0.5, 5, 5),
                          "half in a 5-degree cap");
}

// Welzl: n points in convex position have 2(j+1)(n-j-2) j-facets; for knots
// spread over the sphere every j-facet (j <= 5) has the origin on its far
// side, so they are exactly the degree-j configurations.
TEST(DelaunayConfigurationsTest, CountIdentityForSpreadKnots) {
  for (int n : {50, 1000, 10000}) {
    const Eigen::MatrixX3d knots = UniformKnots(n, 4242 + n);
    DelaunayConfigurationStats stats;
    const auto result = ComputeDelaunayConfigurations(
        knots, 5, DelaunayConfigurationOptions(), &stats);
    ASSERT_TRUE(result.ok()) << result.status().message();
    ASSERT_EQ(stats.configurations_per_degree.size(), 6u);
    for (int k = 0; k <= 5; ++k) {
      EXPECT_EQ(stats.configurations_per_degree[k], 2 * (k + 1) * (n - k - 2))
          << "n=" << n << " k=" << k;
    }
    EXPECT_EQ(CountConfigurations(*result), 2 * 6 * (n - 7));
  }
}

TEST(DelaunayConfigurationsTest, CountIdentityAtEachRequestedDegree) {
  const int n = 3000;
  const Eigen::MatrixX3d knots = UniformKnots(n, 99);
  for (int k = 0; k <= 5; ++k) {
    const auto result = ComputeDelaunayConfigurations(knots, k);
    ASSERT_TRUE(result.ok());
    EXPECT_EQ(CountConfigurations(*result), 2 * (k + 1) * (n - k - 2))
        << "k=" << k;
  }
}

// Every unordered set holds k + 3 distinct knots and each of its boundary
// triples leaves exactly the rest inside its cap (checked knot by knot).
TEST(DelaunayConfigurationsTest, EveryCapHoldsExactlyItsInteriorAtLargeN) {
  const int n = 2000;
  const Eigen::MatrixX3d knots = ClusteredKnots(n, 0.9, 10, 11);
  const auto result = ComputeDelaunayConfigurations(knots, 3);
  ASSERT_TRUE(result.ok());
  // Check a deterministic sample of sets against all knots.
  for (size_t i = 0; i < result->sets.size(); i += 97) {
    const ConfigurationSet& set = result->sets[i];
    ASSERT_EQ(set.knots.size(), 6u);
    for (const auto& b : set.boundaries) {
      const PerturbedCap cap(knots, b[0], b[1], b[2]);
      std::vector<int> inside;
      for (int q = 0; q < n; ++q) {
        if (q != b[0] && q != b[1] && q != b[2] && cap.Contains(q))
          inside.push_back(q);
      }
      std::vector<int> expected;
      for (int x : set.knots) {
        if (x != b[0] && x != b[1] && x != b[2]) expected.push_back(x);
      }
      EXPECT_EQ(inside, expected);
    }
  }
}

TEST(DelaunayConfigurationsTest,
     DegenerateSetsMatchBruteForceUnderThePerturbation) {
  ExpectMatchesBruteForce(IcosahedronKnots(), "icosahedron");
  ExpectMatchesBruteForce(CubeKnots(), "cube");
  ExpectMatchesBruteForce(GreatCirclePlusPoles(12), "great circle + poles");
  ExpectMatchesBruteForce(GreatCirclePlusPoles(40),
                          "great circle (40) + poles");
  ExpectMatchesBruteForce(LatLongGrid(5, 8), "lat-long grid");
  // Two knots 1e-9 apart among uniform ones.
  Eigen::MatrixX3d near = UniformKnots(40, 5);
  near.row(1) =
      (near.row(0) + Eigen::RowVector3d(1e-9, -1e-9, 0.5e-9)).normalized();
  ExpectMatchesBruteForce(near, "near-duplicate");
}

// The perturbed knots are in general and convex position, so the Welzl count
// holds for degenerate but spread sets too, at degrees where no cap of
// j <= k knots can be the larger side.
TEST(DelaunayConfigurationsTest, DegenerateSetsGiveGeneralPositionCounts) {
  const Eigen::MatrixX3d cube = CubeKnots();
  EXPECT_EQ(CountConfigurations(*ComputeDelaunayConfigurations(cube, 0)), 12);
  const Eigen::MatrixX3d ico = IcosahedronKnots();
  for (int k = 0; k <= 2; ++k) {
    EXPECT_EQ(CountConfigurations(*ComputeDelaunayConfigurations(ico, k)),
              2 * (k + 1) * (12 - k - 2));
  }
  const Eigen::MatrixX3d grid = LatLongGrid(20, 36);
  const int n = static_cast<int>(grid.rows());
  for (int k = 0; k <= 5; ++k) {
    EXPECT_EQ(CountConfigurations(*ComputeDelaunayConfigurations(grid, k)),
              2 * (k + 1) * (n - k - 2))
        << "k=" << k;
  }
}

TEST(DelaunayConfigurationsTest,
     OutputIsDeterministicAndThreadCountIndependent) {
  const Eigen::MatrixX3d knots = LatLongGrid(10, 24);
  const auto a = ComputeDelaunayConfigurations(knots, 4);
  DelaunayConfigurationOptions verify;
  verify.always_verify = true;
  const auto b = ComputeDelaunayConfigurations(knots, 4, verify);
  StatusOr<DelaunayConfigurations> c = InvalidArgumentError("not run");
  tbb::task_arena single(1);
  single.execute([&] { c = ComputeDelaunayConfigurations(knots, 4); });
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  ASSERT_EQ(a->sets.size(), b->sets.size());
  ASSERT_EQ(a->sets.size(), c->sets.size());
  for (size_t i = 0; i < a->sets.size(); ++i) {
    EXPECT_EQ(a->sets[i].knots, b->sets[i].knots);
    EXPECT_EQ(a->sets[i].boundaries, b->sets[i].boundaries);
    EXPECT_EQ(a->sets[i].knots, c->sets[i].knots);
    EXPECT_EQ(a->sets[i].boundaries, c->sets[i].boundaries);
  }
}

// The search computes every j-facet (either side of the plane) before
// keeping the configurations; Welzl's count 2(j+1)(n-j-2) holds for them
// whatever the distribution, so it checks completeness on crowded and
// degenerate sets too, at sizes brute force cannot reach.
TEST(DelaunayConfigurationsTest, FacetCountIdentityForAnyDistribution) {
  const std::vector<std::pair<std::string, Eigen::MatrixX3d>> sets = {
      {"all in a 10-degree cap", ClusteredKnots(3000, 1.0, 10, 2)},
      {"90 % in a 10-degree cap", ClusteredKnots(3000, 0.9, 10, 3)},
      {"all in a 100-degree cap", ClusteredKnots(3000, 1.0, 100, 4)},
      {"lat-long grid", LatLongGrid(30, 40)},
      {"great circle + poles", GreatCirclePlusPoles(300)}};
  for (const auto& [label, knots] : sets) {
    const int n = static_cast<int>(knots.rows());
    DelaunayConfigurationStats stats;
    ASSERT_TRUE(ComputeDelaunayConfigurations(
                    knots, 5, DelaunayConfigurationOptions(), &stats)
                    .ok());
    ASSERT_EQ(stats.facets_per_degree.size(), 6u);
    for (int j = 0; j <= 5; ++j) {
      EXPECT_EQ(stats.facets_per_degree[j], 2 * (j + 1) * (n - j - 2))
          << label << " j=" << j;
      EXPECT_LE(stats.configurations_per_degree[j], stats.facets_per_degree[j]);
    }
  }
}

TEST(DelaunayConfigurationsTest, RejectsInvalidInput) {
  const Eigen::MatrixX3d knots = UniformKnots(20, 3);
  EXPECT_EQ(ComputeDelaunayConfigurations(knots, 6).status().code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(ComputeDelaunayConfigurations(knots, -1).status().code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(ComputeDelaunayConfigurations(knots.topRows(8), 5).status().code(),
            StatusCode::kInvalidArgument);
  EXPECT_TRUE(ComputeDelaunayConfigurations(knots.topRows(9), 5).ok());
  Eigen::MatrixX3d bad = knots;
  bad.row(3) *= 1.0 + 1e-8;
  EXPECT_EQ(ComputeDelaunayConfigurations(bad, 2).status().code(),
            StatusCode::kInvalidArgument);
  bad = knots;
  bad(4, 1) = std::nan("");
  EXPECT_EQ(ComputeDelaunayConfigurations(bad, 2).status().code(),
            StatusCode::kInvalidArgument);
  bad = knots;
  bad.row(7) = bad.row(2);
  const auto dup = ComputeDelaunayConfigurations(bad, 2);
  EXPECT_EQ(dup.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(dup.status().message().find("2 and 7"), std::string::npos);
}

}  // namespace
}  // namespace sdcb

namespace sdcb {
namespace {

// Three or more knots within ~1e-8 of each other are no longer in convex
// position once rounded onto the sphere. The result is then either exact
// (equal to brute force) or kInvalidArgument with a message, never wrong.
TEST(DelaunayConfigurationsTest, TightClustersAreExactOrRejected) {
  int rejected = 0;
  for (unsigned seed = 0; seed < 20; ++seed) {
    std::mt19937 rng(seed + 1000);
    std::normal_distribution<double> normal;
    Eigen::MatrixX3d knots = UniformKnots(30, seed);
    for (int i = 1; i < 6; ++i) {
      knots.row(i) =
          (knots.row(0) +
           1e-9 * Eigen::RowVector3d(normal(rng), normal(rng), normal(rng)))
              .normalized();
    }
    const auto oracle = testing::BruteForceConfigurationsUpTo(knots, 2);
    const auto result = ComputeDelaunayConfigurations(knots, 2);
    if (!result.ok()) {
      EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument);
      EXPECT_NE(result.status().message().find("convex hull"),
                std::string::npos)
          << result.status().message();
      ++rejected;
      continue;
    }
    ASSERT_EQ(result->sets.size(), oracle[2].sets.size());
    for (size_t i = 0; i < result->sets.size(); ++i) {
      EXPECT_EQ(result->sets[i].knots, oracle[2].sets[i].knots);
      EXPECT_EQ(result->sets[i].boundaries, oracle[2].sets[i].boundaries);
    }
  }
  EXPECT_GT(rejected, 0);  // the case really occurs at this spacing
}

}  // namespace
}  // namespace sdcb
