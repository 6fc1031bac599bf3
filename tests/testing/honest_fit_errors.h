// Independent checks of the errors a fit reports (core/fit/spline_fitter.h),
// shared by the fitting tests (tests/io/fit_on_cgal_meshes_test.cpp) and the
// long fitting scenarios (tests/long/fit_scenarios_test.cpp):
// - the paper's vertex errors, recomputed from the model's surface at its
//   stored parameters;
// - the surface -> mesh half of the dense two-sided error, against a
//   brute-force point-to-mesh distance at random sphere points.
#ifndef SDCB_TESTS_TESTING_HONEST_FIT_ERRORS_H_
#define SDCB_TESTS_TESTING_HONEST_FIT_ERRORS_H_

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "sdcb/core/fit/spline_fitter.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/spline/spherical_spline.h"

namespace sdcb::testing {

// The largest side of the mesh's bounding box (the errors' 100 %).
inline double BoundingBoxSide(const TriangleMesh& mesh) {
  return (mesh.vertices.colwise().maxCoeff() -
          mesh.vertices.colwise().minCoeff())
      .maxCoeff();
}

// The paper's vertex errors recomputed independently: evaluate the model's
// surface at the stored parameters, map back to input coordinates, compare
// with the mesh.
inline void ExpectHonestVertexErrors(const TriangleMesh& mesh,
                                     const FitResult& fit) {
  const SplineModel& m = fit.model;
  ASSERT_EQ(m.parameters.rows(), mesh.num_vertices());
  auto surface = SurfaceFromModel(m);
  ASSERT_TRUE(surface.ok()) << surface.status().message();
  const Eigen::MatrixX3d f =
      m.transform.ToInput(surface->EvaluateMany(m.parameters));
  const double side = BoundingBoxSide(mesh);
  const Eigen::VectorXd e = 100.0 * (f - mesh.vertices).rowwise().norm() / side;
  const double rmse = std::sqrt(e.squaredNorm() / e.size());
  const RoundStatistics& r = m.statistics.final_result;
  EXPECT_NEAR(rmse, r.vertex_rmse_percent, 1e-6 * r.vertex_rmse_percent);
  EXPECT_NEAR(e.maxCoeff(), r.vertex_max_error_percent,
              1e-6 * r.vertex_max_error_percent);
}

// Distance from q to the triangle (a, b, c): the projection onto its plane
// when it falls inside, else the nearest edge point; infinity for a
// degenerate triangle.
inline double PointTriangleDistance(const Eigen::Vector3d& q,
                                    const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c) {
  auto segment = [&](const Eigen::Vector3d& s, const Eigen::Vector3d& e) {
    const Eigen::Vector3d d = e - s;
    const double t = std::clamp((q - s).dot(d) / d.squaredNorm(), 0.0, 1.0);
    return (q - s - t * d).norm();
  };
  const Eigen::Vector3d n = (b - a).cross(c - a);
  if (!(n.squaredNorm() > 0)) return std::numeric_limits<double>::infinity();
  const Eigen::Vector3d u = n.normalized();
  const Eigen::Vector3d p = q - u * u.dot(q - a);
  if ((b - a).cross(p - a).dot(u) >= 0 && (c - b).cross(p - b).dot(u) >= 0 &&
      (a - c).cross(p - c).dot(u) >= 0) {
    return (q - p).norm();
  }
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

// Distance from q to the mesh over every triangle.
inline double BruteForceDistance(const TriangleMesh& mesh,
                                 const Eigen::Vector3d& q) {
  double best = 1e300;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    best = std::min(
        best, PointTriangleDistance(q, mesh.vertices.row(mesh.faces(f, 0)),
                                    mesh.vertices.row(mesh.faces(f, 1)),
                                    mesh.vertices.row(mesh.faces(f, 2))));
  }
  return best;
}

// Calls visit(s, x) at `points` random sphere points (seed `seed`): s the
// surface's point with its derivatives (normalized frame, whose normals are
// the input's: the transform is a scale and a shift), x its position in the
// input's coordinates.
template <typename Visit>
void ForRandomSurfacePoints(const FitResult& fit, int points, unsigned seed,
                            Visit&& visit) {
  auto surface = SurfaceFromModel(fit.model);
  ASSERT_TRUE(surface.ok());
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss;
  for (int i = 0; i < points; ++i) {
    const Eigen::Vector3d p =
        Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
    const SurfacePoint s =
        surface->EvaluateDifferential(p, JetOrder::kGradient);
    visit(s, Eigen::Vector3d(fit.model.transform.ToInput(s.position.transpose())
                                 .row(0)
                                 .transpose()));
  }
}

// The fold test of core/measure/surface_deviation.h by brute force at `points`
// random sphere points: the spline's normal there against the normals of
// every mesh triangle at the closest distance (within 1e-9 of the
// bounding box's side: all triangles holding the closest point); a point is
// folded when the normal points away from all of them. Returns how many.
inline int BruteForceFoldedPoints(const TriangleMesh& mesh,
                                  const FitResult& fit, int points) {
  const double side = BoundingBoxSide(mesh);
  std::vector<double> distance(mesh.num_faces());
  int folded = 0;
  ForRandomSurfacePoints(
      fit, points, 23, [&](const SurfacePoint& s, const Eigen::Vector3d& x) {
        double closest = 1e300;
        for (int f = 0; f < mesh.num_faces(); ++f) {
          distance[f] =
              PointTriangleDistance(x, mesh.vertices.row(mesh.faces(f, 0)),
                                    mesh.vertices.row(mesh.faces(f, 1)),
                                    mesh.vertices.row(mesh.faces(f, 2)));
          closest = std::min(closest, distance[f]);
        }
        bool opposes_all = true;
        for (int f = 0; f < mesh.num_faces() && opposes_all; ++f) {
          if (distance[f] > closest + 1e-9 * side) continue;
          const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
          const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
          const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
          opposes_all = s.normal.dot((b - a).cross(c - a)) < 0;
        }
        folded += opposes_all;
      });
  return folded;
}

// The surface -> mesh half of the reported error against brute force at
// random sphere points (area-weighted by |du x dv|), in input coordinates.
inline void ExpectHonestSurfaceErrors(const TriangleMesh& mesh,
                                      const FitResult& fit, int points) {
  const double side = BoundingBoxSide(mesh);
  double weight = 0, squares = 0, max = 0;
  ForRandomSurfacePoints(
      fit, points, 17, [&](const SurfacePoint& s, const Eigen::Vector3d& x) {
        const double w = s.du.cross(s.dv).norm();
        const double e = 100 * BruteForceDistance(mesh, x) / side;
        weight += w;
        squares += w * e * e;
        max = std::max(max, e);
      });
  const RoundStatistics& r = fit.model.statistics.final_result;
  // The reported maximum is two-sided and densely sampled: at least what
  // random surface points find; the two-sided rms is at least half of the
  // surface -> mesh one (sqrt of the mean of the two mean squares).
  EXPECT_GE(r.max_error_percent, 0.95 * max);
  EXPECT_GE(r.rmse_percent, 0.9 * std::sqrt(squares / weight / 2));
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_HONEST_FIT_ERRORS_H_
