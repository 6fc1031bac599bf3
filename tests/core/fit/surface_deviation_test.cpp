// The honest error measure (core/fit/surface_deviation.h) and its distance
// oracle (core/mesh/mesh_distance.h) against brute force: point-to-triangle
// distances computed here over every triangle, closest spline points found
// by exhaustive evaluation on ever finer grids, and the orientation
// identities of the fold detector.
#include "sdcb/core/fit/surface_deviation.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "testing/fan_mesh.h"

namespace sdcb {
namespace {

// Closest point of the triangle (a, b, c) to q by cases: the projection onto
// the plane when it falls inside, else the best of the three edges.
Eigen::Vector3d ClosestOnSegment(const Eigen::Vector3d& q,
                                 const Eigen::Vector3d& a,
                                 const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a;
  const double t = std::clamp((q - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return a + t * d;
}

double BruteForceTriangleDistance(const Eigen::Vector3d& q,
                                  const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b,
                                  const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
  const Eigen::Vector3d p = q - n * n.dot(q - a);
  // Inside iff p is on the inner side of all three edges.
  const bool inside = (b - a).cross(p - a).dot(n) >= 0 &&
                      (c - b).cross(p - b).dot(n) >= 0 &&
                      (a - c).cross(p - c).dot(n) >= 0;
  if (inside) return (q - p).norm();
  return std::min({(q - ClosestOnSegment(q, a, b)).norm(),
                   (q - ClosestOnSegment(q, b, c)).norm(),
                   (q - ClosestOnSegment(q, c, a)).norm()});
}

double BruteForceMeshDistance(const TriangleMesh& mesh,
                              const Eigen::Vector3d& q) {
  double best = 1e300;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    best = std::min(
        best, BruteForceTriangleDistance(q, mesh.vertices.row(mesh.faces(f, 0)),
                                         mesh.vertices.row(mesh.faces(f, 1)),
                                         mesh.vertices.row(mesh.faces(f, 2))));
  }
  return best;
}

// An ellipsoid with semi-axes 0.5, 0.35, 0.25 (largest side 1) as a mesh.
TriangleMesh Ellipsoid(int subdivisions) {
  TriangleMesh mesh = MakeIcosphere(subdivisions);
  mesh.vertices.col(0) *= 0.5;
  mesh.vertices.col(1) *= 0.35;
  mesh.vertices.col(2) *= 0.25;
  return mesh;
}

Eigen::MatrixX3d FibonacciSphere(int n) {
  Eigen::MatrixX3d p(n, 3);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1 - z * z);
    p.row(i) << r * std::cos(golden * i), r * std::sin(golden * i), z;
  }
  return p;
}

TEST(MeshDistanceTest, MatchesBruteForceAtRandomPoints) {
  const TriangleMesh mesh = Ellipsoid(2);
  auto tree = MeshDistance::Create(mesh);
  ASSERT_TRUE(tree.ok()) << tree.status().message();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> box(-0.8, 0.8);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d q(box(rng), box(rng), box(rng));
    const MeshDistance::Closest c = tree->Find(q);
    EXPECT_NEAR(c.distance, BruteForceMeshDistance(mesh, q), 1e-12);
    // The reported face holds the reported point.
    EXPECT_NEAR(BruteForceTriangleDistance(
                    c.point, mesh.vertices.row(mesh.faces(c.face, 0)),
                    mesh.vertices.row(mesh.faces(c.face, 1)),
                    mesh.vertices.row(mesh.faces(c.face, 2))),
                0.0, 1e-12);
  }
}

// A CAD fan's needles are held as pieces in the tree (each needle cut along
// its length): distances, faces and normals must still be those of the
// whole triangles.
TEST(MeshDistanceTest, NeedlesCutIntoPiecesKeepTheirDistancesAndFaces) {
  const TriangleMesh cone = testing::DoubleCone(3000);
  auto tree = MeshDistance::Create(cone);
  ASSERT_TRUE(tree.ok()) << tree.status().message();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> box(-1.2, 1.2);
  for (int i = 0; i < 150; ++i) {
    const Eigen::Vector3d q(box(rng), box(rng), box(rng));
    const MeshDistance::Closest c = tree->Find(q);
    EXPECT_NEAR(c.distance, BruteForceMeshDistance(cone, q), 1e-12);
    ASSERT_GE(c.face, 0);
    ASSERT_LT(c.face, cone.num_faces());
    EXPECT_NEAR(BruteForceTriangleDistance(
                    c.point, cone.vertices.row(cone.faces(c.face, 0)),
                    cone.vertices.row(cone.faces(c.face, 1)),
                    cone.vertices.row(cone.faces(c.face, 2))),
                0.0, 1e-12);
    // Outward-oriented cone: the outward direction from the point is never
    // opposed, the inward one always (away from the tips and the rim).
    const Eigen::Vector3d n = tree->FaceNormal(c.face);
    EXPECT_GT(n.dot(c.point), 0.0);
    EXPECT_FALSE(tree->Opposes(c, c.point));
  }
}

TEST(MeshDistanceTest, RefusesAMeshWithoutTriangles) {
  TriangleMesh flat;
  flat.vertices.resize(3, 3);
  flat.vertices << 0, 0, 0, 1, 0, 0, 2, 0, 0;  // collinear
  flat.faces.resize(1, 3);
  flat.faces << 0, 1, 2;
  EXPECT_EQ(MeshDistance::Create(flat).status().code(),
            StatusCode::kInvalidInput);
}

class SurfaceDeviationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    mesh_ = new TriangleMesh(Ellipsoid(3));
    FitOptions options;
    options.rmse_percent = 0.05;
    options.max_rounds = 2;
    auto fit = FitSphericalSpline(*mesh_, options);
    ASSERT_TRUE(fit.ok()) << fit.status().message();
    model_ = new SplineModel(fit->model);
    // The mesh in the model's frame (the fit normalized it).
    mesh_->vertices = model_->transform.ToNormalized(mesh_->vertices);
  }
  static void TearDownTestSuite() {
    delete mesh_;
    delete model_;
  }
  static TriangleMesh* mesh_;
  static SplineModel* model_;
};
TriangleMesh* SurfaceDeviationTest::mesh_ = nullptr;
SplineModel* SurfaceDeviationTest::model_ = nullptr;

TEST_F(SurfaceDeviationTest, SurfaceToMeshAgreesWithBruteForce) {
  auto surface = SurfaceFromModel(*model_);
  ASSERT_TRUE(surface.ok());
  auto d = MeasureSurfaceDeviation(*surface, *mesh_);
  ASSERT_TRUE(d.ok()) << d.status().message();
  EXPECT_GE(d->surface_samples, 100000);
  // Area-weighted Monte Carlo estimate at 4,000 random sphere points, the
  // weight being the area element |du x dv| of the surface there.
  std::mt19937 rng(11);
  std::normal_distribution<double> gauss;
  double weight = 0, squares = 0, max = 0;
  for (int i = 0; i < 4000; ++i) {
    const Eigen::Vector3d p =
        Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
    const SurfacePoint s =
        surface->EvaluateDifferential(p, JetOrder::kGradient);
    const double w = s.du.cross(s.dv).norm();
    const double e = 100 * BruteForceMeshDistance(*mesh_, s.position);
    weight += w;
    squares += w * e * e;
    max = std::max(max, e);
  }
  const double rms = std::sqrt(squares / weight);
  EXPECT_NEAR(d->surface_to_mesh_rms_percent, rms, 0.1 * rms);
  // 100,000 lattice samples find at least about the maximum that 4,000
  // random ones do.
  EXPECT_GE(d->surface_to_mesh_max_percent, 0.95 * max);
  EXPECT_EQ(d->folded_area_percent, 0.0);
}

TEST_F(SurfaceDeviationTest, MeshToSurfaceIsTheClosestSplinePoint) {
  auto surface = SurfaceFromModel(*model_);
  ASSERT_TRUE(surface.ok());
  auto d = MeasureSurfaceDeviation(*surface, *mesh_);
  ASSERT_TRUE(d.ok()) << d.status().message();
  // Brute force: the nearest of 50,000 evaluated spline points, then the
  // nearest of a 41 x 41 grid of sphere points around it spanning two
  // spacings of the cloud (so accurate to ~1e-4 of the cloud's spacing).
  const Eigen::MatrixX3d directions = FibonacciSphere(50000);
  const Eigen::MatrixX3d cloud = surface->EvaluateMany(directions);
  const double spacing = std::sqrt(4 * M_PI / 50000);
  const Eigen::MatrixX3d fitted = surface->EvaluateMany(model_->parameters);
  for (int v = 0; v < mesh_->num_vertices(); v += 16) {
    const Eigen::RowVector3d x = mesh_->vertices.row(v);
    Eigen::Index best;
    (cloud.rowwise() - x).rowwise().norm().minCoeff(&best);
    Eigen::Vector3d center = directions.row(best).transpose(), e_u, e_v;
    double brute = 1e300;
    for (int pass = 0; pass < 4; ++pass) {
      TangentFrame(center, &e_u, &e_v);
      const double span = 2 * spacing / std::pow(10.0, pass);
      Eigen::MatrixX3d grid(41 * 41, 3);
      for (int i = 0; i < 41; ++i) {
        for (int j = 0; j < 41; ++j) {
          grid.row(41 * i + j) = (center + span * (i - 20) / 20.0 * e_u +
                                  span * (j - 20) / 20.0 * e_v)
                                     .normalized()
                                     .transpose();
        }
      }
      const Eigen::MatrixX3d local = surface->EvaluateMany(grid);
      Eigen::Index k;
      brute = 100 * (local.rowwise() - x).rowwise().norm().minCoeff(&k);
      center = grid.row(k).transpose();
    }
    const double measured = d->vertex_distance_percent[v];
    // Not below the true distance (every reported distance is to a spline
    // point), at most 1 % above it (the search's documented tolerance).
    EXPECT_GE(measured, brute - 1e-5) << "vertex " << v;
    EXPECT_LE(measured, 1.01 * brute + 1e-7) << "vertex " << v;
    // Never above the parametric bound |F(u_i) - x_i| by more than that.
    EXPECT_LE(
        measured,
        1.01 * 100 * (fitted.row(v) - mesh_->vertices.row(v)).norm() + 1e-7);
  }
}

TEST_F(SurfaceDeviationTest, ReversingTheMeshOrientationFoldsEverything) {
  auto surface = SurfaceFromModel(*model_);
  ASSERT_TRUE(surface.ok());
  TriangleMesh reversed = *mesh_;
  reversed.faces.col(1).swap(reversed.faces.col(2));
  DeviationOptions options;
  options.min_surface_samples = 20000;
  auto d = MeasureSurfaceDeviation(*surface, reversed, options);
  ASSERT_TRUE(d.ok());
  EXPECT_GT(d->folded_area_percent, 99.9);
}

TEST_F(SurfaceDeviationTest, AMirroredCapIsFoldedAndNothingElse) {
  // Control points beyond x = 0.3 mirrored through that plane: the surface
  // over that cap turns inside out.
  SplineModel folded = *model_;
  for (Eigen::Index i = 0; i < folded.control_points.rows(); ++i) {
    if (folded.control_points(i, 0) > 0.3) {
      folded.control_points(i, 0) = 0.6 - folded.control_points(i, 0);
    }
  }
  auto original = SurfaceFromModel(*model_);
  auto surface = SurfaceFromModel(folded);
  ASSERT_TRUE(original.ok() && surface.ok());
  DeviationOptions options;
  options.min_surface_samples = 20000;
  auto d = MeasureSurfaceDeviation(*surface, *mesh_, options);
  ASSERT_TRUE(d.ok());
  EXPECT_GT(d->folded_area_percent, 1.0);
  const Eigen::MatrixX3d before =
      original->EvaluateMany(d->surface_sample_points);
  int folded_samples = 0;
  for (Eigen::Index i = 0; i < before.rows(); ++i) {
    if (!d->surface_sample_folded[i]) continue;
    ++folded_samples;
    // Only where the mirrored control points act.
    EXPECT_GT(before(i, 0), 0.2) << "sample " << i;
  }
  EXPECT_GT(folded_samples, 0);
}

TEST_F(SurfaceDeviationTest, CandidatesOnlyModeBoundsTheClosestPoints) {
  auto surface = SurfaceFromModel(*model_);
  ASSERT_TRUE(surface.ok());
  const Eigen::MatrixX3d fitted = surface->EvaluateMany(model_->parameters);
  DeviationOptions options;
  options.min_surface_samples = 20000;
  auto exact = MeasureSurfaceDeviation(*surface, *mesh_, options);
  options.closest_points = false;
  auto bound = MeasureSurfaceDeviation(*surface, *mesh_, options, &fitted);
  ASSERT_TRUE(exact.ok() && bound.ok());
  EXPECT_GE(bound->mesh_to_surface_rms_percent,
            exact->mesh_to_surface_rms_percent);
  EXPECT_EQ(bound->surface_to_mesh_rms_percent,
            exact->surface_to_mesh_rms_percent);
  // Without candidates the bound cannot be formed.
  EXPECT_EQ(MeasureSurfaceDeviation(*surface, *mesh_, options).status().code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace sdcb
