// The data-term samples (core/fit/fit_samples.h) on a CAD-style fan, whose
// needle triangles cut along their length would ask for thousands of
// samples per control point.
#include "sdcb/core/fit/fit_samples.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "testing/fan_mesh.h"

namespace sdcb {
namespace {

// n points spread over the unit sphere (a Fibonacci lattice).
Eigen::MatrixX3d FibonacciPoints(int n) {
  Eigen::MatrixX3d p(n, 3);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n;
    const double r = std::sqrt(1.0 - z * z);
    p.row(i) << r * std::cos(golden * i), r * std::sin(golden * i), z;
  }
  return p;
}

// The double cone's area in closed form: 2n triangles with base
// 2 sin(pi / n) and height sqrt(1 + cos^2(pi / n)).
double DoubleConeArea(int n) {
  const double c = std::cos(M_PI / n);
  return 2 * n * 0.5 * 2 * std::sin(M_PI / n) * std::sqrt(1 + c * c);
}

TEST(FitSamplesTest, CappedPiecesStillIntegrateTheWholeSurface) {
  const int n = 2000;
  const TriangleMesh cone = testing::DoubleCone(n);
  // The cone is star-shaped about its centre: radial projection is a
  // bijective parameterization.
  const Eigen::MatrixX3d sphere = cone.vertices.rowwise().normalized();
  const Eigen::MatrixX3d knots = FibonacciPoints(400);
  const double area = DoubleConeArea(n);

  const FitSamples free = BuildFitSamples(cone, sphere, knots);
  FitSampleOptions capped_options;
  capped_options.max_pieces = 20000;
  const FitSamples capped =
      BuildFitSamples(cone, sphere, knots, capped_options);

  // Every piece of the surface is weighted once: the weights add up to its
  // area, capped or not.
  EXPECT_NEAR(free.weights.sum(), area, 1e-9 * area);
  EXPECT_NEAR(capped.weights.sum(), area, 1e-9 * area);
  // Uncapped, the needles are cut along their length, many times over the
  // cap; capped, their pieces are pooled into cells of the sample spacing:
  // far fewer rows, as dense as the knots ask.
  const Eigen::Index free_rows = free.points.rows() - free.num_vertices;
  const Eigen::Index capped_rows = capped.points.rows() - capped.num_vertices;
  EXPECT_GT(free_rows, 4 * capped_options.max_pieces);
  // Pooled, and the needles cut into a few staggered strips each rather
  // than along their whole length: far less work than uncapped.
  EXPECT_GT(capped.merged_pieces, 0);
  EXPECT_LT(capped.merged_pieces, free_rows / 4);
  EXPECT_LE(capped_rows, capped_options.max_pieces);
  EXPECT_GT(capped_rows, 0);
  EXPECT_EQ(capped.samples_per_spacing, 2.0);
  // As dense as the knots ask everywhere: every knot has a sample within
  // its sample spacing (its spacing over samples_per_spacing), as uncapped.
  const Eigen::VectorXd spacing = KnotSpacing(knots);
  for (const FitSamples* samples : {&free, &capped}) {
    int far = 0;
    for (Eigen::Index k = 0; k < knots.rows(); ++k) {
      const double nearest = (samples->points.rowwise() - knots.row(k))
                                 .rowwise()
                                 .norm()
                                 .minCoeff();
      far += nearest > spacing[k] / 2.0;
    }
    EXPECT_EQ(far, 0);
  }
  // Samples are on the sphere; targets on the cone (|z| = 1 - r) up to the
  // pooling: a cell's mean lies inside the cone by at most a few percent of
  // the sample spacing (~0.08 here), at the tips, where a normal bin's
  // wedge of needles (~30 degrees) is averaged.
  double worst = 0;
  for (Eigen::Index i = 0; i < capped.points.rows(); ++i) {
    EXPECT_NEAR(capped.points.row(i).norm(), 1.0, 1e-12);
    const Eigen::Vector3d x = capped.targets.row(i);
    worst = std::max(worst, std::abs(std::abs(x.z()) + x.head<2>().norm() - 1));
  }
  EXPECT_LT(worst, 0.02 * spacing.minCoeff() / 2.0);
}

// The triangles are split in parallel and a full budget stops the split
// early; the one-thread run is the oracle: at the smallest budget that holds
// every piece (split samples) and one below it (pooled samples), 4 threads
// give its samples bit for bit, whichever thread finds the budget full.
TEST(FitSamplesTest, SameSamplesForAnyThreadCountAtTheBudget) {
  const TriangleMesh cone = testing::DoubleCone(300);
  const Eigen::MatrixX3d sphere = cone.vertices.rowwise().normalized();
  const Eigen::MatrixX3d knots = FibonacciPoints(200);
  auto build = [&](int64_t max_pieces, int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              threads);
    FitSampleOptions options;
    options.max_pieces = max_pieces;
    return BuildFitSamples(cone, sphere, knots, options);
  };
  // The smallest budget without pooling, by bisection on the sequential
  // result.
  int64_t low = 1, high = 1;
  while (build(high, 1).merged_pieces > 0) high *= 2;
  while (low < high) {
    const int64_t mid = (low + high) / 2;
    if (build(mid, 1).merged_pieces > 0) {
      low = mid + 1;
    } else {
      high = mid;
    }
  }
  ASSERT_GT(high, 1000);  // the needles are split into many pieces
  for (int64_t budget : {high - 1, high, int64_t{0}}) {
    const FitSamples sequential = build(budget, 1);
    const FitSamples parallel = build(budget, 4);
    EXPECT_EQ(sequential.merged_pieces > 0, budget == high - 1) << budget;
    EXPECT_EQ(sequential.points, parallel.points) << budget;
    EXPECT_EQ(sequential.targets, parallel.targets) << budget;
    EXPECT_EQ(sequential.weights, parallel.weights) << budget;
    EXPECT_EQ(sequential.triangle, parallel.triangle) << budget;
    EXPECT_EQ(sequential.split_triangles, parallel.split_triangles) << budget;
  }
}

}  // namespace
}  // namespace sdcb
