// The spline's normal beside the input's sharp edges, against the input's
// triangles (the oracle of the feature tests and of
// bench/feature_normals_bench.cpp): for every feature edge and each of its
// two triangles, the points of the triangle at `offset` (normalized frame:
// largest bounding-box side 1) from the edge at a quarter, half and three
// quarters of it (points that leave the triangle are skipped), each matched
// to the nearest of a dense sample of the surface (a Fibonacci lattice of
// the sphere, evaluated with normals), whose normal is compared with the
// triangle's. Nothing of the fit is used: only the surface and the mesh.
#ifndef SDCB_TESTS_TESTING_FEATURE_NORMALS_H_
#define SDCB_TESTS_TESTING_FEATURE_NORMALS_H_

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/feature_curves.h"
#include "sdcb/core/sphere/point_kd_tree.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "testing/random_sphere_points.h"

namespace sdcb::testing {

struct FeatureNormals {
  std::vector<double> angles_degrees;  // one per point
  double max_degrees = 0.0;
  double median_degrees = 0.0;
  // The largest distance from a point to its surface sample (how far the
  // sample is from the point it stands for).
  double max_sample_gap = 0.0;
};

// `vertices`: the mesh's vertices in the spline's (normalized) frame.
inline FeatureNormals MeasureFeatureNormals(const SphericalSpline& spline,
                                            const Eigen::MatrixX3d& vertices,
                                            const Eigen::MatrixX3i& faces,
                                            const MeshFeatures& features,
                                            double offset, int samples) {
  const Eigen::MatrixX3d lattice = FibonacciPoints(samples, 0, 0.0);
  const std::vector<SurfacePoint> surface =
      spline.EvaluateDifferentialMany(lattice, JetOrder::kGradient);
  Eigen::MatrixX3d positions(samples, 3);
  for (int i = 0; i < samples; ++i) positions.row(i) = surface[i].position;
  const PointKdTree tree(positions);

  std::map<std::array<int, 2>, std::vector<int>> edge_faces;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = faces(f, k), b = faces(f, (k + 1) % 3);
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(
          static_cast<int>(f));
    }
  }
  FeatureNormals out;
  for (const std::array<int, 2>& edge : features.edges) {
    const Eigen::Vector3d a = vertices.row(edge[0]).transpose();
    const Eigen::Vector3d b = vertices.row(edge[1]).transpose();
    for (const int f : edge_faces[edge]) {
      Eigen::Vector3d c = a;
      for (int k = 0; k < 3; ++k) {
        const int v = faces(f, k);
        if (v != edge[0] && v != edge[1]) c = vertices.row(v).transpose();
      }
      const Eigen::Vector3d p0 = vertices.row(faces(f, 0)).transpose();
      const Eigen::Vector3d p1 = vertices.row(faces(f, 1)).transpose();
      const Eigen::Vector3d p2 = vertices.row(faces(f, 2)).transpose();
      const Eigen::Vector3d normal = (p1 - p0).cross(p2 - p0).normalized();
      Eigen::Vector3d inward = normal.cross((b - a).normalized());
      if (inward.dot(c - a) < 0) inward = -inward;
      const double area = (b - a).cross(c - a).dot(normal);
      for (const double t : {0.25, 0.5, 0.75}) {
        const Eigen::Vector3d x = a + t * (b - a) + offset * inward;
        const double wa = (b - x).cross(c - x).dot(normal) / area;
        const double wb = (c - x).cross(a - x).dot(normal) / area;
        if (wa < 0 || wb < 0 || 1.0 - wa - wb < 0) continue;
        const PointKdTree::Neighbor n = tree.Nearest(x);
        const Eigen::Vector3d m = surface[n.index].normal;
        const double angle =
            std::atan2(m.cross(normal).norm(), m.dot(normal)) * 180.0 / kPi;
        out.angles_degrees.push_back(angle);
        out.max_degrees = std::max(out.max_degrees, angle);
        out.max_sample_gap =
            std::max(out.max_sample_gap, std::sqrt(n.squared_distance));
      }
    }
  }
  if (!out.angles_degrees.empty()) {
    std::vector<double> sorted = out.angles_degrees;
    std::sort(sorted.begin(), sorted.end());
    out.median_degrees = sorted[sorted.size() / 2];
  }
  return out;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_FEATURE_NORMALS_H_
