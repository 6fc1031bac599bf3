// The boundary distance of a trimmed spline (core/measure/
// boundary_deviation.h) against brute force: the trims' images sampled a
// hundred times more densely, evaluated point by point, and every distance
// to every segment of the other boundary taken.
#include "sdcb/core/measure/boundary_deviation.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>
#include <vector>

#include "sdcb/core/fit/spline_fitter.h"
#include "testing/open_sphere.h"

namespace sdcb {
namespace {

double SegmentDistance(const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                       const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a;
  const double t = std::clamp((q - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (a + t * d - q).norm();
}

// The largest distance from a point of `from` to the closed polyline `to`
// (both closed polylines, `from` sampled `per_edge` times per edge).
double BruteForceOneWay(const std::vector<Eigen::Vector3d>& from,
                        const std::vector<Eigen::Vector3d>& to, int per_edge) {
  double worst = 0;
  for (size_t i = 0; i < from.size(); ++i) {
    const Eigen::Vector3d a = from[i], b = from[(i + 1) % from.size()];
    for (int k = 0; k < per_edge; ++k) {
      const Eigen::Vector3d q =
          a + (b - a) * (static_cast<double>(k) / per_edge);
      double best = 1e300;
      for (size_t j = 0; j < to.size(); ++j) {
        best =
            std::min(best, SegmentDistance(q, to[j], to[(j + 1) % to.size()]));
      }
      worst = std::max(worst, best);
    }
  }
  return worst;
}

// The point of the great-circle arc from a to b at fraction t of its angle.
Eigen::Vector3d OnArc(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                      double t) {
  const double angle = std::atan2(a.cross(b).norm(), a.dot(b));
  return ((std::sin((1 - t) * angle) * a + std::sin(t * angle) * b) /
          std::sin(angle))
      .normalized();
}

class BoundaryDeviationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    FitOptions options;
    options.rmse_percent = 0.5;
    options.max_rounds = 1;
    options.final_surface_samples = 1000;
    options.final_mesh_samples = 0;
    auto fit = FitSphericalSpline(
        testing::OpenEllipsoid(2, Eigen::Vector3d(1.0, 0.8, 0.6), {}), options);
    ASSERT_TRUE(fit.ok()) << fit.status().message();
    auto surface = SurfaceFromModel(fit->model);
    ASSERT_TRUE(surface.ok());
    surface_ = new SphericalSpline(std::move(surface).value());
  }
  static void TearDownTestSuite() { delete surface_; }
  static SphericalSpline* surface_;
};
SphericalSpline* BoundaryDeviationTest::surface_ = nullptr;

// Two loops (circles of latitude, 9 and 14 points) and "part" boundaries
// off their images by random offsets up to 0.02: the measurement agrees
// with brute force both ways.
TEST_F(BoundaryDeviationTest, MatchesBruteForceBothWays) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> offset(-0.02, 0.02);
  std::vector<TrimLoop> trims;
  std::vector<Eigen::MatrixX3d> loops;
  for (const auto& [z, n] : {std::pair<double, int>{0.5, 9}, {-0.3, 14}}) {
    TrimLoop trim;
    trim.points.resize(n, 3);
    for (int i = 0; i < n; ++i) {
      const double phi = 2 * 3.14159265358979323846 * i / n;
      const double r = std::sqrt(1 - z * z);
      trim.points.row(i) << r * std::cos(phi), r * std::sin(phi), z;
    }
    Eigen::MatrixX3d x = surface_->EvaluateMany(trim.points);
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
      x.row(i) += Eigen::RowVector3d(offset(rng), offset(rng), offset(rng));
    }
    trims.push_back(trim);
    loops.push_back(x);
  }
  const double unit = 2.0;
  StatusOr<BoundaryDeviation> d =
      MeasureBoundaryDeviation(*surface_, trims, loops, unit, 0.01);
  ASSERT_TRUE(d.ok()) << d.status().message();

  double to_mesh = 0, to_surface = 0;
  for (size_t l = 0; l < trims.size(); ++l) {
    // The spline's boundary, 1000 points per arc; the part's, its loop.
    std::vector<Eigen::Vector3d> image, part;
    const Eigen::MatrixX3d& u = trims[l].points;
    for (Eigen::Index i = 0; i < u.rows(); ++i) {
      const Eigen::Vector3d a = u.row(i), b = u.row((i + 1) % u.rows());
      for (int k = 0; k < 1000; ++k) {
        image.push_back(
            surface_->Evaluate(OnArc(a, b, k / 1000.0)).transpose());
      }
      part.push_back(loops[l].row(i).transpose());
    }
    to_mesh = std::max(to_mesh, BruteForceOneWay(image, part, 1));
    to_surface = std::max(to_surface, BruteForceOneWay(part, image, 1000));
  }
  to_mesh *= 100 / unit;
  to_surface *= 100 / unit;
  EXPECT_GT(to_mesh, 0.2);  // the offsets are seen
  // Sampled 0.01 radians apart against 100 times more densely: the same to
  // a few thousandths of a percent.
  EXPECT_NEAR(d->surface_to_mesh_max_percent, to_mesh, 0.003);
  EXPECT_NEAR(d->mesh_to_surface_max_percent, to_surface, 0.003);
  EXPECT_EQ(d->max_percent(), std::max(d->surface_to_mesh_max_percent,
                                       d->mesh_to_surface_max_percent));
  EXPECT_GT(d->samples, 1000);
}

// The same loops given as boundary edges of a mesh, in a scrambled order
// and without the correspondence (as `sdcb compare` has them): the same
// brute force both ways.
TEST_F(BoundaryDeviationTest, BoundaryEdgesInAnyOrderMatchBruteForce) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> offset(-0.02, 0.02);
  std::vector<TrimLoop> trims;
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector2i> edges;
  std::vector<std::vector<Eigen::Vector3d>> loops;
  for (const auto& [z, n, m] :
       {std::tuple<double, int, int>{0.4, 11, 17}, {-0.5, 8, 5}}) {
    TrimLoop trim;
    trim.points.resize(n, 3);
    const double r = std::sqrt(1 - z * z);
    for (int i = 0; i < n; ++i) {
      const double phi = 2 * 3.14159265358979323846 * i / n;
      trim.points.row(i) << r * std::cos(phi), r * std::sin(phi), z;
    }
    trims.push_back(trim);
    // The mesh's loop: m points of its own near the image of the circle.
    std::vector<Eigen::Vector3d> loop;
    const int first = static_cast<int>(vertices.size());
    for (int i = 0; i < m; ++i) {
      const double phi = 2 * 3.14159265358979323846 * (i + 0.3) / m;
      const Eigen::Vector3d u(r * std::cos(phi), r * std::sin(phi), z);
      Eigen::Vector3d x = surface_->Evaluate(u).transpose();
      x += Eigen::Vector3d(offset(rng), offset(rng), offset(rng));
      loop.push_back(x);
      vertices.push_back(x);
      edges.emplace_back(first + i, first + (i + 1) % m);
    }
    loops.push_back(loop);
  }
  std::shuffle(edges.begin(), edges.end(), rng);
  Eigen::MatrixX3d x(static_cast<Eigen::Index>(vertices.size()), 3);
  for (size_t i = 0; i < vertices.size(); ++i) {
    x.row(static_cast<Eigen::Index>(i)) = vertices[i].transpose();
  }
  Eigen::MatrixX2i e(static_cast<Eigen::Index>(edges.size()), 2);
  for (size_t i = 0; i < edges.size(); ++i) {
    e.row(static_cast<Eigen::Index>(i)) = edges[i].transpose();
  }
  const double unit = 2.0;
  StatusOr<BoundaryDeviation> d =
      MeasureBoundaryDeviation(*surface_, trims, x, e, unit, 0.01, 0.002);
  ASSERT_TRUE(d.ok()) << d.status().message();

  // Brute force: every loop's image against every mesh loop, both ways.
  std::vector<std::vector<Eigen::Vector3d>> images;
  for (const TrimLoop& trim : trims) {
    std::vector<Eigen::Vector3d> image;
    const Eigen::MatrixX3d& u = trim.points;
    for (Eigen::Index i = 0; i < u.rows(); ++i) {
      const Eigen::Vector3d a = u.row(i), b = u.row((i + 1) % u.rows());
      for (int k = 0; k < 1000; ++k) {
        image.push_back(
            surface_->Evaluate(OnArc(a, b, k / 1000.0)).transpose());
      }
    }
    images.push_back(image);
  }
  double to_mesh = 0, to_surface = 0;
  for (const auto& image : images) {
    for (const Eigen::Vector3d& q : image) {
      double best = 1e300;
      for (const auto& loop : loops) {
        best = std::min(best, BruteForceOneWay({q}, loop, 1));
      }
      to_mesh = std::max(to_mesh, best);
    }
  }
  for (const auto& loop : loops) {
    for (size_t i = 0; i < loop.size(); ++i) {
      const Eigen::Vector3d a = loop[i], b = loop[(i + 1) % loop.size()];
      for (int k = 0; k < 200; ++k) {
        const Eigen::Vector3d q = a + (b - a) * (k / 200.0);
        double best = 1e300;
        for (const auto& image : images) {
          best = std::min(best, BruteForceOneWay({q}, image, 1));
        }
        to_surface = std::max(to_surface, best);
      }
    }
  }
  to_mesh *= 100 / unit;
  to_surface *= 100 / unit;
  EXPECT_GT(to_mesh, 0.2);
  EXPECT_NEAR(d->surface_to_mesh_max_percent, to_mesh, 0.003);
  EXPECT_NEAR(d->mesh_to_surface_max_percent, to_surface, 0.003);
  // An edge out of range, a step not positive: refused.
  Eigen::MatrixX2i bad = e;
  bad(0, 1) = static_cast<int>(x.rows());
  EXPECT_EQ(
      MeasureBoundaryDeviation(*surface_, trims, x, bad, unit, 0.01, 0.002)
          .status()
          .code(),
      StatusCode::kInvalidArgument);
  EXPECT_EQ(MeasureBoundaryDeviation(*surface_, trims, x, e, unit, 0.01, 0.0)
                .status()
                .code(),
            StatusCode::kInvalidArgument);
}

// Steps far below what any boundary needs (a hostile request) end in at
// most 250,000 samples a side, measuring as a sensible step does.
TEST_F(BoundaryDeviationTest, TinyStepsKeepToTheSampleBudget) {
  TrimLoop trim;
  const int n = 12;
  trim.points.resize(n, 3);
  Eigen::MatrixX3d x(n, 3);
  Eigen::MatrixX2i edges(n, 2);
  for (int i = 0; i < n; ++i) {
    const double phi = 2 * 3.14159265358979323846 * i / n;
    trim.points.row(i) << 0.8 * std::cos(phi), 0.8 * std::sin(phi), 0.6;
    edges.row(i) << i, (i + 1) % n;
  }
  x = surface_->EvaluateMany(trim.points);
  x.col(2).array() += 0.01;
  StatusOr<BoundaryDeviation> tiny =
      MeasureBoundaryDeviation(*surface_, {trim}, x, edges, 1.0, 1e-12, 1e-12);
  ASSERT_TRUE(tiny.ok()) << tiny.status().message();
  EXPECT_LE(tiny->samples, 250000 + 4 * n);
  StatusOr<BoundaryDeviation> sensible =
      MeasureBoundaryDeviation(*surface_, {trim}, x, edges, 1.0, 1e-3, 1e-4);
  ASSERT_TRUE(sensible.ok());
  EXPECT_NEAR(tiny->max_percent(), sensible->max_percent(), 1e-3);
  EXPECT_GT(sensible->max_percent(), 0.9);  // the loop is 1 % off
}

TEST_F(BoundaryDeviationTest, RefusesLoopsThatDoNotMatchTheTrims) {
  TrimLoop trim;
  trim.points.resize(3, 3);
  trim.points << 1, 0, 0, 0, 1, 0, 0, 0, 1;
  EXPECT_EQ(MeasureBoundaryDeviation(*surface_, {trim}, {}, 1.0, 0.01)
                .status()
                .code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(MeasureBoundaryDeviation(*surface_, {trim},
                                     {Eigen::MatrixX3d::Zero(4, 3)}, 1.0, 0.01)
                .status()
                .code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(MeasureBoundaryDeviation(*surface_, {trim},
                                     {Eigen::MatrixX3d::Zero(3, 3)}, 0.0, 0.01)
                .status()
                .code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace sdcb
