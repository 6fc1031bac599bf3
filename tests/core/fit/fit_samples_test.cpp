// The data-term samples (core/fit/fit_samples.h) on a CAD-style fan, whose
// needle triangles cut along their length would ask for thousands of
// samples per control point.
#include "sdcb/core/fit/fit_samples.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <map>
#include <tuple>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/icosphere.h"
#include "testing/fan_mesh.h"
#include "testing/make_mesh.h"

namespace sdcb {
namespace {

// n points spread over the unit sphere (a Fibonacci lattice).
Eigen::MatrixX3d FibonacciPoints(int n) {
  Eigen::MatrixX3d p(n, 3);
  const double golden = kPi * (3.0 - std::sqrt(5.0));
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
  const double c = std::cos(kPi / n);
  return 2 * n * 0.5 * 2 * std::sin(kPi / n) * std::sqrt(1 + c * c);
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

// An ellipsoid with axes (1, 0.7, 0.4) meshed by an icosphere of 10,242
// vertices, parameterized by the icosphere's own vertices (a bijection).
struct DenseEllipsoid {
  TriangleMesh mesh;
  Eigen::MatrixX3d sphere;
};
DenseEllipsoid MakeDenseEllipsoid() {
  DenseEllipsoid e;
  e.mesh = MakeIcosphere(5);
  e.sphere = e.mesh.vertices.rowwise().normalized();
  e.mesh.vertices = e.sphere * Eigen::Vector3d(1.0, 0.7, 0.4).asDiagonal();
  return e;
}

// A mesh far denser than its knots (10,242 vertices, 60 knots) thinned to
// the knots' density: far fewer rows; each kept row is one of the full
// quadrature's rows, bit for bit (a point of the mesh with its own sphere
// point, not an average); the weights still add up to the area; every
// vertex's cell row lies within its cell of the vertex; and the rows still
// integrate a smooth function of the surface like the full quadrature.
TEST(FitSamplesTest, ThinnedRowsAreRowsOfTheFullQuadratureAtTheKnotsDensity) {
  const DenseEllipsoid e = MakeDenseEllipsoid();
  const Eigen::MatrixX3d knots = FibonacciPoints(60);
  const FitSamples full = BuildFitSamples(e.mesh, e.sphere, knots);
  ASSERT_FALSE(full.thinned);
  FitSampleOptions options;
  options.thin_above_vertices = 1;
  const FitSamples thin = BuildFitSamples(e.mesh, e.sphere, knots, options);
  ASSERT_TRUE(thin.thinned);
  EXPECT_EQ(thin.unthinned_rows, full.points.rows());
  EXPECT_EQ(thin.num_vertices, 0);
  const Eigen::Index rows = thin.points.rows();
  EXPECT_LT(rows, full.points.rows() / 3);
  EXPECT_GT(rows, 16 * knots.rows());  // about 4 x 4 cells per knot

  // Kept rows are full rows: the same point and target, bit for bit, and
  // the vertex (or triangle) they are.
  std::map<std::tuple<double, double, double>, Eigen::Index> full_row;
  for (Eigen::Index r = 0; r < full.points.rows(); ++r) {
    full_row[{full.points(r, 0), full.points(r, 1), full.points(r, 2)}] = r;
  }
  for (Eigen::Index r = 0; r < rows; ++r) {
    const auto it = full_row.find(
        {thin.points(r, 0), thin.points(r, 1), thin.points(r, 2)});
    ASSERT_NE(it, full_row.end()) << r;
    const Eigen::Index f = it->second;
    EXPECT_EQ(thin.points.row(r), full.points.row(f));
    EXPECT_EQ(thin.targets.row(r), full.targets.row(f));
    if (f < full.num_vertices) {
      EXPECT_EQ(thin.row_vertex[r], f);
      EXPECT_EQ(thin.triangle[r], -1);
    } else {
      EXPECT_EQ(thin.row_vertex[r], -1);
      EXPECT_EQ(thin.triangle[r], full.triangle[f - full.num_vertices]);
    }
  }
  EXPECT_NEAR(thin.weights.sum(), full.weights.sum(),
              1e-12 * full.weights.sum());

  // A vertex's cell row: within a cell's diagonal (sqrt 2 h, h = a knot's
  // spacing over 4, at most the largest spacing) of the vertex on the
  // sphere.
  const double largest_cell = KnotSpacing(knots).maxCoeff() / 4.0;
  ASSERT_EQ(thin.vertex_row.size(), static_cast<size_t>(e.mesh.num_vertices()));
  for (int v = 0; v < e.mesh.num_vertices(); ++v) {
    const int r = thin.vertex_row[v];
    ASSERT_GE(r, 0);
    ASSERT_LT(r, rows);
    EXPECT_LE((thin.points.row(r) - e.sphere.row(v)).norm(),
              1.5 * std::sqrt(2.0) * largest_cell)
        << v;
  }

  // The integral of z^2 over the surface, by each quadrature.
  auto integral = [](const FitSamples& q) {
    return q.weights.dot(q.targets.col(2).cwiseAbs2());
  };
  EXPECT_NEAR(integral(thin), integral(full), 0.02 * integral(full));
}

// Thinning decides by sorted cells, not by the threads' order: the same
// rows for 1 and 4 threads.
TEST(FitSamplesTest, ThinnedSamplesAreTheSameForAnyThreadCount) {
  const DenseEllipsoid e = MakeDenseEllipsoid();
  const Eigen::MatrixX3d knots = FibonacciPoints(60);
  auto build = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              threads);
    FitSampleOptions options;
    options.thin_above_vertices = 1;
    return BuildFitSamples(e.mesh, e.sphere, knots, options);
  };
  const FitSamples one = build(1), four = build(4);
  EXPECT_EQ(one.points, four.points);
  EXPECT_EQ(one.targets, four.targets);
  EXPECT_EQ(one.weights, four.weights);
  EXPECT_EQ(one.triangle, four.triangle);
  EXPECT_EQ(one.row_vertex, four.row_vertex);
  EXPECT_EQ(one.vertex_row, four.vertex_row);
}

// Vertices not above the threshold, or cells that would keep most rows: no
// thinning, the full quadrature.
TEST(FitSamplesTest, NoThinningWhenItWouldKeepMostRows) {
  const DenseEllipsoid e = MakeDenseEllipsoid();
  const Eigen::MatrixX3d knots = FibonacciPoints(60);
  const FitSamples full = BuildFitSamples(e.mesh, e.sphere, knots);
  FitSampleOptions options;
  options.thin_above_vertices = e.mesh.num_vertices();  // not above
  EXPECT_FALSE(BuildFitSamples(e.mesh, e.sphere, knots, options).thinned);
  options.thin_above_vertices = 1;
  options.thinned_cells_per_spacing = 200.0;  // cells finer than the mesh
  const FitSamples fine = BuildFitSamples(e.mesh, e.sphere, knots, options);
  EXPECT_FALSE(fine.thinned);
  EXPECT_EQ(fine.points, full.points);
  EXPECT_EQ(fine.weights, full.weights);
}

// Rows beside an edge: on the octahedron (vertices at distance 1, sphere
// points the vertices themselves) a point of a triangle maps to its own
// direction, so each row's sphere point is its target's direction; and each
// lies inside a triangle at the edge, about the asked distance off the
// edge's great circle.
TEST(FitSamplesTest, EdgeBandRowsLieBesideTheEdgeAtTheirOffsets) {
  const TriangleMesh octahedron = testing::MakeMesh(
      {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
      {{0, 2, 4},
       {2, 1, 4},
       {1, 3, 4},
       {3, 0, 4},
       {2, 0, 5},
       {1, 2, 5},
       {3, 1, 5},
       {0, 3, 5}});
  FitSamples samples;
  samples.points.resize(0, 3);
  samples.targets.resize(0, 3);
  const std::vector<double> offsets = {1e-6, 1e-4};
  AppendEdgeBandSamples(octahedron, octahedron.vertices, {{0, 2}}, offsets, 5,
                        0.25, &samples);
  ASSERT_EQ(samples.points.rows(), 2 * 2 * 5);  // 2 triangles, 2 offsets, 5
  ASSERT_EQ(samples.triangle.size(), 20u);
  const Eigen::Vector3d pole = Eigen::Vector3d(0, 0, 1);  // x-y great circle
  for (Eigen::Index r = 0; r < 20; ++r) {
    const Eigen::Vector3d point = samples.points.row(r);
    const Eigen::Vector3d target = samples.targets.row(r);
    EXPECT_NEAR((point - target.normalized()).norm(), 0.0, 1e-12);
    EXPECT_NEAR(target.cwiseAbs().sum(), 1.0, 1e-12);  // on a face
    EXPECT_TRUE(samples.triangle[r] == 0 || samples.triangle[r] == 4);
    const double off = std::asin(std::abs(point.dot(pole)));
    const double asked = offsets[(r / 5) % 2];
    EXPECT_GT(off, 0.5 * asked);
    EXPECT_LT(off, 2.0 * asked);
    EXPECT_EQ(samples.weights[r], 0.25);
  }
}

}  // namespace
}  // namespace sdcb
