// The honest error measure (core/measure/surface_deviation.h) and its distance
// oracle (core/mesh/mesh_distance.h) against brute force: point-to-triangle
// distances computed here over every triangle, closest spline points found
// by exhaustive evaluation on ever finer grids, and the orientation
// identities of the fold detector.
#include "sdcb/core/measure/surface_deviation.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/mesh/mesh_distance.h"
#include "sdcb/core/sphere/sphere_geometry.h"
#include "sdcb/core/spline/dcb_basis.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "testing/fan_mesh.h"
#include "testing/make_mesh.h"
#include "testing/special_knots.h"

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
  const double golden = kPi * (3.0 - std::sqrt(5.0));
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

// FindNear starts from a given point of the mesh: the true closest point
// whether that start is near (the previous query's), far (the opposite
// side) or on a needle held as pieces (the start's face then has several).
TEST(MeshDistanceTest, FindNearFindsTheClosestPointFromAnyStart) {
  for (const TriangleMesh& mesh : {Ellipsoid(2), testing::DoubleCone(3000)}) {
    auto tree = MeshDistance::Create(mesh);
    ASSERT_TRUE(tree.ok()) << tree.status().message();
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> box(-1.0, 1.0);
    MeshDistance::Closest previous = tree->Find({0, 0, 0});
    for (int i = 0; i < 300; ++i) {
      const Eigen::Vector3d q(box(rng), box(rng), box(rng));
      const double truth = BruteForceMeshDistance(mesh, q);
      const MeshDistance::Closest far = tree->Find(-q);
      for (const MeshDistance::Closest& start : {previous, far}) {
        const MeshDistance::Closest c = tree->FindNear(q, start);
        EXPECT_NEAR(c.distance, truth, 1e-12);
        ASSERT_GE(c.face, 0);
        EXPECT_NEAR(BruteForceTriangleDistance(
                        c.point, mesh.vertices.row(mesh.faces(c.face, 0)),
                        mesh.vertices.row(mesh.faces(c.face, 1)),
                        mesh.vertices.row(mesh.faces(c.face, 2))),
                    0.0, 1e-12);
      }
      previous = tree->FindNear(q, previous);
    }
  }
}

// The mesh's normal at a closest point: the face's inside it, the
// normalized sum of the normals of the triangles sharing an edge or a vertex
// on it, whichever triangle Find reports (closed forms on the cube).
TEST(MeshDistanceTest, TheNormalOnAnEdgeOrAVertexIsTheirTrianglesSum) {
  const TriangleMesh cube = testing::CubeMesh();
  auto tree = MeshDistance::Create(cube);
  ASSERT_TRUE(tree.ok());
  const auto normal_at = [&](const Eigen::Vector3d& q) {
    return tree->Normal(tree->Find(q));
  };
  // Inside the face z = 1.
  EXPECT_LT((normal_at({0.3, -0.2, 2}) - Eigen::Vector3d(0, 0, 1)).norm(),
            1e-12);
  // On the edge x = y = 1 (triangles 4 and 5 on x = 1, 10 and 11 on y = 1:
  // one of each holds the edge's middle).
  EXPECT_LT(
      (normal_at({2, 2, 0.1}) - Eigen::Vector3d(1, 1, 0).normalized()).norm(),
      1e-12);
  // On the diagonal of the face z = 1 (two triangles of the same plane).
  EXPECT_LT((normal_at({0.1, 0.1, 2}) - Eigen::Vector3d(0, 0, 1)).norm(),
            1e-12);
  // At the corner (1, 1, 1), vertex 6: the sum of the normals of the
  // triangles around it, as many per face as the triangulation has there.
  const MeshDistance::Closest corner = tree->Find({2, 2, 2});
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int f = 0; f < cube.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (cube.faces(f, k) == 6) sum += tree->FaceNormal(f);
    }
  }
  EXPECT_LT((tree->Normal(corner) - sum.normalized()).norm(), 1e-12);
  EXPECT_GT(sum.normalized().dot(Eigen::Vector3d(1, 1, 1).normalized()), 0.9);
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

// The distance from x to a spline by exhaustive evaluation: the nearest of
// `n` evaluated spline points (a Fibonacci cloud of directions), then
// `passes` times the nearest of a (2 half + 1)^2 grid of sphere points
// around it spanning two spacings of the cloud, each pass ten times finer.
class BruteForceSpline {
 public:
  BruteForceSpline(const SphericalSpline& surface, int n)
      : surface_(surface),
        directions_(FibonacciSphere(n)),
        cloud_(surface.EvaluateMany(directions_)),
        spacing_(std::sqrt(4 * kPi / n)) {}

  double Distance(const Eigen::Vector3d& x, int passes, int half) const {
    const int side = 2 * half + 1;
    Eigen::Index best;
    (cloud_.rowwise() - x.transpose()).rowwise().norm().minCoeff(&best);
    Eigen::Vector3d center = directions_.row(best).transpose(), e_u, e_v;
    double distance = (cloud_.row(best).transpose() - x).norm();
    for (int pass = 0; pass < passes; ++pass) {
      TangentFrame(center, &e_u, &e_v);
      const double span = 2 * spacing_ / std::pow(10.0, pass);
      Eigen::MatrixX3d grid(side * side, 3);
      for (int i = 0; i < side; ++i) {
        for (int j = 0; j < side; ++j) {
          grid.row(side * i + j) = (center + span * (i - half) / half * e_u +
                                    span * (j - half) / half * e_v)
                                       .normalized()
                                       .transpose();
        }
      }
      const Eigen::MatrixX3d local = surface_.EvaluateMany(grid);
      Eigen::Index k;
      distance =
          (local.rowwise() - x.transpose()).rowwise().norm().minCoeff(&k);
      center = grid.row(k).transpose();
    }
    return distance;
  }

 private:
  const SphericalSpline& surface_;
  Eigen::MatrixX3d directions_;
  Eigen::MatrixX3d cloud_;
  double spacing_;
};

// Where I = sum B_i = 0 the surface is 0 / 0. The cube's knots at degree 2
// leave such holes (DcbBasis::Create refuses them unless its coverage check
// is off): the measurement names a point of one instead of handing NaN to
// CGAL's exact predicates (which trap on it).
TEST(SurfaceDeviationHoleTest, ASurfaceWithAHoleIsNamedNotMeasured) {
  const Eigen::MatrixX3d knots = testing::CubeKnots();
  auto configurations = ComputeDelaunayConfigurations(knots, 2);
  ASSERT_TRUE(configurations.ok());
  DcbBasisOptions unchecked;
  unchecked.coverage_samples = 0;
  auto basis = DcbBasis::Create(knots, *configurations, unchecked);
  ASSERT_TRUE(basis.ok()) << basis.status().message();
  // Each control point the mean of its set's knots: a closed blob.
  Eigen::MatrixX3d control_points(basis->size(), 3);
  for (int i = 0; i < basis->size(); ++i) {
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    for (const int k : configurations->sets[i].knots) sum += knots.row(k);
    control_points.row(i) =
        sum / static_cast<double>(configurations->sets[i].knots.size());
  }
  auto surface = SphericalSpline::Create(*basis, control_points);
  ASSERT_TRUE(surface.ok()) << surface.status().message();
  DeviationOptions options;
  options.min_surface_samples = 5000;
  auto deviation = MeasureSurfaceDeviation(*surface, MakeIcosphere(2), options);
  ASSERT_FALSE(deviation.ok());
  EXPECT_EQ(deviation.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(deviation.status().message().find("the surface is undefined near"),
            std::string::npos)
      << deviation.status().message();
}

// The mesh -> surface half given per sample (the fit's rounds): the rms
// is the area-weighted one and the maximum is over the samples that stand
// for area; a sample of weight 0 (an open part's fill, not measured) is
// left out of both, whatever its distance.
TEST(SetMeshToSurfaceTest, TheMaximumLeavesOutSamplesOfNoArea) {
  Eigen::VectorXd distance(5), weight(5);
  distance << 0.1, 7.0, 0.4, 0.3, 9.0;
  weight << 2.0, 0.0, 1.0, 1.0, 0.0;
  SurfaceDeviation d;
  d.surface_to_mesh_rms_percent = 0.2;
  d.surface_to_mesh_max_percent = 0.25;
  SetMeshToSurface(distance, weight, &d);
  // By hand: the weighted mean square (2 0.01 + 0.16 + 0.09) / 4.
  EXPECT_NEAR(d.mesh_to_surface_rms_percent, std::sqrt(0.27 / 4), 1e-15);
  EXPECT_EQ(d.mesh_to_surface_max_percent, 0.4);
  EXPECT_EQ(d.hausdorff_percent, 0.4);
  EXPECT_NEAR(d.rms_percent, std::sqrt(0.5 * (0.04 + 0.27 / 4)), 1e-15);
}

class SurfaceDeviationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    mesh_ = new TriangleMesh(Ellipsoid(3));
    FitOptions options;
    options.rmse_percent = 0.05;
    options.max_rounds = 2;
    // The fit's own dense measurements kept small (they would take most of
    // its time, once per test process): these tests measure the model
    // themselves.
    options.final_surface_samples = 1000;
    options.final_mesh_samples = 0;
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
  const BruteForceSpline brute_force(*surface, 50000);
  const Eigen::MatrixX3d fitted = surface->EvaluateMany(model_->parameters);
  for (int v = 0; v < mesh_->num_vertices(); v += 16) {
    const double brute =
        100 * brute_force.Distance(mesh_->vertices.row(v).transpose(), 4, 20);
    const double measured = d->vertex_distance_percent[v];
    // Not below the true distance (every reported distance is to a spline
    // point), at most 1 % above it where the search refines (the documented
    // tolerance, for distances at least the mesh -> surface rms; below it
    // the lattice's point stands: pessimistic, and under the rms).
    EXPECT_GE(measured, brute - 1e-5) << "vertex " << v;
    if (measured >= d->mesh_to_surface_rms_percent) {
      EXPECT_LE(measured, 1.01 * brute + 1e-7) << "vertex " << v;
    }
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

// A mesh whose vertices are points of the spline (its values at an
// icosphere's directions), measured with a coarse lattice: the lattice's
// image is then far from many of them, and its spline point as far, yet
// each vertex's true distance is 0. The largest distance found must be a
// searched one, not the image's: within the closest-point search's
// accuracy of 0.
TEST_F(SurfaceDeviationTest, MeshPointsOnTheSplineAreFoundWhateverTheLattice) {
  auto surface = SurfaceFromModel(*model_);
  ASSERT_TRUE(surface.ok());
  TriangleMesh on_spline = MakeIcosphere(4);
  on_spline.vertices = surface->EvaluateMany(on_spline.vertices);
  DeviationOptions options;
  options.min_surface_samples = 1000;
  auto d = MeasureSurfaceDeviation(*surface, on_spline, options);
  ASSERT_TRUE(d.ok()) << d.status().message();
  EXPECT_LE(d->mesh_to_surface_max_percent, 1e-4);
}

// A coarse mesh of the same ellipsoid (42 vertices, on the ellipsoid like the
// fitted one's): at its vertices it is within the fit's error of the spline,
// inside its 80 triangles up to ~1.5 % away. Measured at the vertices alone the
// mesh -> surface half misses that; with mesh_samples it measures the
// triangles, and agrees with brute force at random points inside them: the
// rms within the Monte Carlo estimate's few per cent, the maximum at least
// theirs and confirmed by brute force where it was found, and the bound
// above every one of them and near the maximum.
TEST_F(SurfaceDeviationTest,
       MeshSamplesInsideTrianglesMeasureWhatVerticesMiss) {
  auto surface = SurfaceFromModel(*model_);
  ASSERT_TRUE(surface.ok());
  TriangleMesh coarse = Ellipsoid(1);
  coarse.vertices = model_->transform.ToNormalized(coarse.vertices);
  DeviationOptions options;
  options.min_surface_samples = 20000;
  auto at_vertices = MeasureSurfaceDeviation(*surface, coarse, options);
  options.mesh_samples = 20000;
  auto dense = MeasureSurfaceDeviation(*surface, coarse, options);
  ASSERT_TRUE(at_vertices.ok() && dense.ok());
  EXPECT_EQ(at_vertices->mesh_samples, 42);
  EXPECT_EQ(at_vertices->mesh_sample_spacing_percent, 0.0);
  // About the samples asked for, and the points the bound added.
  EXPECT_GT(dense->mesh_samples, 15000);
  EXPECT_LT(dense->mesh_samples, 40000);
  EXPECT_GT(dense->mesh_sample_spacing_percent, 0.0);
  EXPECT_EQ(dense->vertex_distance_percent.size(), 42);
  ASSERT_EQ(dense->mesh_sample_points.rows(), dense->mesh_samples);
  ASSERT_EQ(dense->mesh_sample_distance_percent.size(), dense->mesh_samples);
  // The input's vertices keep their distances (within the search's 1 %:
  // whether a vertex is searched depends on the largest distance among
  // the points measured with it), and are the first samples.
  for (int v = 0; v < 42; ++v) {
    EXPECT_NEAR(dense->vertex_distance_percent[v],
                at_vertices->vertex_distance_percent[v],
                0.01 * at_vertices->vertex_distance_percent[v] + 1e-12)
        << "vertex " << v;
  }
  EXPECT_EQ(dense->mesh_sample_points.topRows(42), coarse.vertices);
  EXPECT_EQ(dense->surface_to_mesh_rms_percent,
            at_vertices->surface_to_mesh_rms_percent);
  // The samples' weights are the mesh's area.
  double mesh_area = 0;
  std::vector<double> area(coarse.num_faces());
  for (int f = 0; f < coarse.num_faces(); ++f) {
    const Eigen::Vector3d a = coarse.vertices.row(coarse.faces(f, 0));
    const Eigen::Vector3d b = coarse.vertices.row(coarse.faces(f, 1));
    const Eigen::Vector3d c = coarse.vertices.row(coarse.faces(f, 2));
    area[f] = 0.5 * (b - a).cross(c - a).norm();
    mesh_area += area[f];
  }
  EXPECT_NEAR(dense->mesh_sample_weight.sum(), mesh_area, 1e-12 * mesh_area);
  // Brute force at 600 points uniform in area over the triangles.
  const BruteForceSpline brute_force(*surface, 50000);
  std::mt19937 rng(5);
  std::discrete_distribution<int> pick(area.begin(), area.end());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double squares = 0, max = 0;
  constexpr int kPoints = 600;
  for (int i = 0; i < kPoints; ++i) {
    const int f = pick(rng);
    double r1 = unit(rng), r2 = unit(rng);
    if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
    const Eigen::Vector3d a = coarse.vertices.row(coarse.faces(f, 0));
    const Eigen::Vector3d b = coarse.vertices.row(coarse.faces(f, 1));
    const Eigen::Vector3d c = coarse.vertices.row(coarse.faces(f, 2));
    const double e =
        100 * brute_force.Distance(a + r1 * (b - a) + r2 * (c - a), 3, 10);
    squares += e * e;
    max = std::max(max, e);
  }
  const double rms = std::sqrt(squares / kPoints);
  // The vertices see a small part of it.
  EXPECT_LT(at_vertices->mesh_to_surface_max_percent, 0.3 * max);
  EXPECT_LT(at_vertices->mesh_to_surface_rms_percent, 0.3 * rms);
  EXPECT_NEAR(dense->mesh_to_surface_rms_percent, rms, 0.05 * rms);
  // The maximum at least the random points' (the true one lies between
  // them, and brute force confirms the largest sample's below).
  EXPECT_GE(dense->mesh_to_surface_max_percent, max - 1e-6);
  // The bound: above every point's distance (vertices alone too, from the
  // whole triangles), and near the maximum once refined (the refinement adds
  // up to 10,000 points while the bound is more than 1 % above it; the
  // distance is large over most of this coarse mesh, so it may end first).
  EXPECT_GE(at_vertices->mesh_to_surface_max_bound_percent, max);
  EXPECT_GE(dense->mesh_to_surface_max_bound_percent, max);
  EXPECT_GE(dense->mesh_to_surface_max_bound_percent,
            dense->mesh_to_surface_max_percent);
  EXPECT_GT(dense->mesh_bound_samples, 0);
  EXPECT_LE(dense->mesh_bound_samples, 10000);
  EXPECT_LE(dense->mesh_to_surface_max_bound_percent,
            1.03 * dense->mesh_to_surface_max_percent)
      << dense->mesh_to_surface_max_percent;
  // The largest sample's distance is a real one: brute force agrees.
  Eigen::Index worst;
  dense->mesh_sample_distance_percent.maxCoeff(&worst);
  const double brute_worst =
      100 * brute_force.Distance(
                dense->mesh_sample_points.row(worst).transpose(), 4, 20);
  EXPECT_NEAR(dense->mesh_to_surface_max_percent, brute_worst,
              0.01 * brute_worst);
  EXPECT_EQ(dense->hausdorff_percent,
            std::max(dense->mesh_to_surface_max_percent,
                     dense->surface_to_mesh_max_percent));
  // Without closest points there is no candidate inside a triangle.
  options.closest_points = false;
  const Eigen::MatrixX3d candidates = Eigen::MatrixX3d::Zero(42, 3);
  EXPECT_EQ(MeasureSurfaceDeviation(*surface, coarse, options, &candidates)
                .status()
                .code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace sdcb
