#include "sdcb/core/tessellate/optimal_triangle_count.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "sdcb/core/mesh/icosphere.h"

namespace sdcb {
namespace {

// Adds one flat triangle's area, weighted by sqrt(|K|) of its part.
void Accumulate(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                const Eigen::Vector3d& p2, double k, CurvatureIntegrals* out) {
  const double area = 0.5 * (p1 - p0).cross(p2 - p0).norm();
  out->area += area;
  if (!std::isfinite(k)) return;
  if (k > 0) out->convex += area * std::sqrt(k);
  if (k < 0) out->saddle += area * std::sqrt(-k);
}

}  // namespace

StatusOr<CurvatureIntegrals> IntegrateCurvature(
    const SurfaceSampler& surface, const Eigen::MatrixX3d& directions,
    const Eigen::MatrixX3i& faces, int levels) {
  // Sub-triangles of the unit triangle, as barycentric corner weights:
  // the regular split of order n = 2^levels.
  const int n = 1 << std::max(0, levels);
  std::vector<std::array<Eigen::Vector3d, 3>> subs;
  auto w = [n](int i, int j) -> Eigen::Vector3d {
    return Eigen::Vector3d(i, j, n - i - j) / n;
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      subs.push_back({w(i, j), w(i + 1, j), w(i, j + 1)});
      if (i + j + 1 < n)
        subs.push_back({w(i + 1, j), w(i + 1, j + 1), w(i, j + 1)});
    }
  const Eigen::Index per = static_cast<Eigen::Index>(subs.size());
  // Per sub-triangle: 3 corners and the centroid.
  Eigen::MatrixX3d points(faces.rows() * per * 4, 3);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d a = directions.row(faces(f, 0)).transpose();
    const Eigen::Vector3d b = directions.row(faces(f, 1)).transpose();
    const Eigen::Vector3d c = directions.row(faces(f, 2)).transpose();
    for (Eigen::Index s = 0; s < per; ++s) {
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d& x = subs[s][k];
        centroid += x / 3.0;
        points.row((f * per + s) * 4 + k) =
            (x[0] * a + x[1] * b + x[2] * c).normalized().transpose();
      }
      points.row((f * per + s) * 4 + 3) =
          (centroid[0] * a + centroid[1] * b + centroid[2] * c)
              .normalized()
              .transpose();
    }
  }
  // Curvature (the expensive part) at the centroids only.
  const Eigen::Index count = points.rows() / 4;
  Eigen::MatrixX3d centroids(count, 3);
  for (Eigen::Index t = 0; t < count; ++t)
    centroids.row(t) = points.row(4 * t + 3);
  Eigen::VectorXd gaussian, mean;
  if (!surface.SampleCurvature(centroids, &gaussian, &mean)) {
    return InvalidArgumentError("the surface sampler has no curvature");
  }
  Eigen::MatrixX3d positions;
  surface.Sample(points, &positions, nullptr);
  CurvatureIntegrals out;
  for (Eigen::Index t = 0; t < count; ++t) {
    Accumulate(positions.row(4 * t).transpose(),
               positions.row(4 * t + 1).transpose(),
               positions.row(4 * t + 2).transpose(), gaussian[t], &out);
  }
  return out;
}

StatusOr<CurvatureIntegrals> IntegrateCurvatureOverSurface(
    const SurfaceSampler& surface, int level) {
  if (level < 0 || level > 8) {
    return InvalidArgumentError("the quadrature level must be in [0, 8]");
  }
  const TriangleMesh sphere = MakeIcosphere(level);
  Eigen::MatrixX3d centroids(sphere.faces.rows(), 3);
  for (Eigen::Index f = 0; f < sphere.faces.rows(); ++f) {
    centroids.row(f) = (sphere.vertices.row(sphere.faces(f, 0)) +
                        sphere.vertices.row(sphere.faces(f, 1)) +
                        sphere.vertices.row(sphere.faces(f, 2)))
                           .normalized();
  }
  Eigen::VectorXd gaussian, mean;
  if (!surface.SampleCurvature(centroids, &gaussian, &mean)) {
    return InvalidArgumentError("the surface sampler has no curvature");
  }
  Eigen::MatrixX3d positions;
  surface.Sample(sphere.vertices, &positions, nullptr);
  CurvatureIntegrals out;
  for (Eigen::Index f = 0; f < sphere.faces.rows(); ++f) {
    Accumulate(positions.row(sphere.faces(f, 0)).transpose(),
               positions.row(sphere.faces(f, 1)).transpose(),
               positions.row(sphere.faces(f, 2)).transpose(), gaussian[f],
               &out);
  }
  return out;
}

double OptimalTriangleCount(const CurvatureIntegrals& integrals, double eps) {
  return (kConvexTriangleConstant * integrals.convex +
          kSaddleTriangleConstant * integrals.saddle) /
         eps;
}

}  // namespace sdcb
