// With FitOptions::keep_features the fit keeps sharp corners and edges with
// the corners' knot clusters (core/knots/feature_knots.h), judged by the
// dense two-sided measurement and by the spline's normals beside the edges
// against the input's triangles (tests/testing/feature_normals.h); and it
// leaves every other fit as it was.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/mesh/icosphere.h"
#include "testing/feature_normals.h"
#include "testing/make_mesh.h"
#include "testing/random_sphere_points.h"

namespace sdcb {
namespace {

// Keeping features on (FitOptions::keep_features), at this angle.
FitOptions Options(double feature_angle) {
  FitOptions options;
  options.rmse_percent = 0.1;
  options.feature_angle_degrees = feature_angle;
  options.keep_features = true;
  return options;
}

TEST(FeatureFitTest, TheCubeKeepsItsEdgesWithAFewHundredControlPoints) {
  const TriangleMesh cube = testing::CubeMesh();
  auto fit = FitSphericalSpline(cube, Options(30));
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  EXPECT_TRUE(fit->shortfall.empty()) << fit->shortfall;
  EXPECT_TRUE(fit->features_kept);
  EXPECT_EQ(fit->features.corners.size(), 8u);
  const RoundStatistics& f = fit->model.statistics.final_result;
  EXPECT_EQ(f.knots, 32);  // 8 corners x (1 + 3)
  EXPECT_LE(f.control_points, 300);
  EXPECT_LE(f.max_error_percent, 0.2);  // dense, both ways
  EXPECT_EQ(f.folded_area_percent, 0.0);
  auto spline = SurfaceFromModel(fit->model);
  ASSERT_TRUE(spline.ok());
  // Beside every edge (1 % of the side from it, both faces) the normal is
  // the face's: the edges are creases, not fillets.
  const Eigen::MatrixX3d vertices =
      fit->model.transform.ToNormalized(cube.vertices);
  const testing::FeatureNormals normals = testing::MeasureFeatureNormals(
      *spline, vertices, cube.faces, fit->features, 0.01, 150000);
  EXPECT_EQ(normals.angles_degrees.size(), 72u);
  EXPECT_LT(normals.max_degrees, 2.0);
  std::printf("cube: %d control points, max %.4f %%, normals %.4f deg\n",
              f.control_points, f.max_error_percent, normals.max_degrees);
  // The parameterization is the central projection up to the edges: the
  // sphere point p maps to the cube's point along p (side 1 in the
  // normalized frame), also 1e-6 to 1e-4 radians off an edge's arc, where
  // only the rows beside the edges pin the thin triangles' basis
  // functions (without them the points slide along the edge by 0.14).
  double slide = 0.0;
  for (int i = 0; i < 8; ++i) {
    for (int j = i + 1; j < 8; ++j) {
      const Eigen::Vector3d a = cube.vertices.row(i).normalized();
      const Eigen::Vector3d b = cube.vertices.row(j).normalized();
      if (std::abs(a.dot(b) - 1.0 / 3.0) > 1e-9) continue;  // not an edge
      const Eigen::Vector3d side = a.cross(b).normalized();
      for (int s = 1; s < 40; ++s) {
        const Eigen::Vector3d on = (a * (40 - s) + b * s).normalized();
        for (const double offset :
             {-1e-4, -2.5e-5, -1e-6, 1e-6, 2.5e-5, 1e-4}) {
          const Eigen::Vector3d p = (on + offset * side).normalized();
          const Eigen::Vector3d cube_point = 0.5 * p / p.cwiseAbs().maxCoeff();
          slide = std::max(slide, (spline->Evaluate(p) - cube_point).norm());
        }
      }
    }
  }
  std::printf("cube: the spline off the central projection by %.3g\n", slide);
  EXPECT_LT(slide, 1e-3);

  // Without keep_features the fit gets no clusters; its round 0, of
  // 100 knots placed by curvature, rounds the edges.
  FitOptions smooth_options;
  smooth_options.rmse_percent = 0.1;
  smooth_options.max_rounds = 1;
  smooth_options.keep_features = false;
  auto smooth = FitSphericalSpline(cube, smooth_options);
  ASSERT_TRUE(smooth.ok());
  EXPECT_FALSE(smooth->features_kept);
  auto rounded = SurfaceFromModel(smooth->model);
  ASSERT_TRUE(rounded.ok());
  EXPECT_GT(testing::MeasureFeatureNormals(*rounded, vertices, cube.faces,
                                           fit->features, 0.01, 150000)
                .max_degrees,
            5.0);
}

// The tetrahedron of CGAL's data/meshes/tetrahedron.off.
TriangleMesh Tetrahedron() {
  return testing::MakeMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                           {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}});
}

TEST(FeatureFitTest, TheTetrahedronKeepsItsEdgesWithFourKnotsAlongEach) {
  // Each edge's great circle holds that edge alone: one knot along it from
  // each corner gives the circle four knots, one fewer than a crease needs
  // at degree 4 (that round misses), four give it ten.
  const TriangleMesh tetrahedron = Tetrahedron();
  auto fit = FitSphericalSpline(tetrahedron, Options(30));
  ASSERT_TRUE(fit.ok()) << fit.status().message();
  EXPECT_TRUE(fit->shortfall.empty()) << fit->shortfall;
  EXPECT_TRUE(fit->features_kept);
  const RoundStatistics& f = fit->model.statistics.final_result;
  EXPECT_EQ(f.knots, 52);  // 4 corners x (1 + 3 edges x 4)
  EXPECT_LE(f.control_points, 400);
  EXPECT_EQ(f.folded_area_percent, 0.0);
  auto spline = SurfaceFromModel(fit->model);
  ASSERT_TRUE(spline.ok());
  // The closed form: every surface point on one of the four face planes,
  // none outside the solid (in the normalized frame, against the largest
  // side 1), and the normal beside every edge the face's.
  const Eigen::MatrixX3d vertices =
      fit->model.transform.ToNormalized(tetrahedron.vertices);
  std::vector<Eigen::Vector4d> planes;
  for (Eigen::Index t = 0; t < tetrahedron.faces.rows(); ++t) {
    const Eigen::Vector3d a = vertices.row(tetrahedron.faces(t, 0));
    const Eigen::Vector3d b = vertices.row(tetrahedron.faces(t, 1));
    const Eigen::Vector3d c = vertices.row(tetrahedron.faces(t, 2));
    Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    // Outward (the file's faces turn inward): the centroid below the plane.
    if (n.dot(vertices.colwise().mean().transpose() - a) > 0) n = -n;
    planes.push_back({n.x(), n.y(), n.z(), -n.dot(a)});
  }
  const Eigen::MatrixX3d lattice = testing::FibonacciPoints(20000, 0, 0.0);
  double off_faces = 0.0, outside = 0.0;
  for (Eigen::Index i = 0; i < lattice.rows(); ++i) {
    const Eigen::Vector4d x = spline->Evaluate(lattice.row(i)).homogeneous();
    double nearest = 1e300, out = -1e300;
    for (const Eigen::Vector4d& plane : planes) {
      nearest = std::min(nearest, std::abs(plane.dot(x)));
      out = std::max(out, plane.dot(x));
    }
    off_faces = std::max(off_faces, nearest);
    outside = std::max(outside, out);
  }
  EXPECT_LT(off_faces, 1e-4);
  EXPECT_LT(outside, 1e-4);
  const testing::FeatureNormals normals = testing::MeasureFeatureNormals(
      *spline, vertices, tetrahedron.faces, fit->features, 0.01, 150000);
  EXPECT_EQ(normals.angles_degrees.size(), 36u);
  EXPECT_LT(normals.max_degrees, 2.0);
  std::printf(
      "tetrahedron: %d control points, %.2g off the faces, normals %.4f "
      "deg\n",
      f.control_points, off_faces, normals.max_degrees);
}

TEST(FeatureFitTest, AFitTheClustersCannotFinishIsTheOneWithoutThem) {
  // The tetrahedron at degree 3: both cluster rounds (one and three knots
  // along each edge) fold a little, so the fit is the one it would be
  // without features.
  const TriangleMesh tetrahedron = Tetrahedron();
  FitOptions with_options = Options(30), without_options = Options(180);
  with_options.degree = without_options.degree = 3;
  with_options.max_rounds = without_options.max_rounds = 2;
  auto with = FitSphericalSpline(tetrahedron, with_options);
  auto without = FitSphericalSpline(tetrahedron, without_options);
  ASSERT_TRUE(with.ok() && without.ok());
  EXPECT_EQ(with->features.corners.size(), 4u);
  EXPECT_FALSE(with->features_kept);
  EXPECT_EQ(with->model.knots, without->model.knots);
  EXPECT_EQ(with->model.control_points, without->model.control_points);
  EXPECT_EQ(with->model.statistics.rounds.size(),
            without->model.statistics.rounds.size());
}

TEST(FeatureFitTest, NoCreaseWhereTheMeshHasNone) {
  // A smooth mesh (an ellipsoid) has no features: the same fit as with
  // feature detection off, bit for bit.
  TriangleMesh ellipsoid = MakeIcosphere(2);
  ellipsoid.vertices.col(0) *= 2.0;
  auto with = FitSphericalSpline(ellipsoid, Options(30));
  auto without = FitSphericalSpline(ellipsoid, Options(180));
  ASSERT_TRUE(with.ok() && without.ok());
  EXPECT_TRUE(with->features.edges.empty());
  EXPECT_FALSE(with->features_kept);
  EXPECT_EQ(with->model.knots, without->model.knots);
  EXPECT_EQ(with->model.control_points, without->model.control_points);
}

}  // namespace
}  // namespace sdcb
