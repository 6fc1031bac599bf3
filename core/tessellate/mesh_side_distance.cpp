#include "sdcb/core/tessellate/mesh_side_distance.h"

#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>

#include "sdcb/core/measure/closest_surface_points.h"

namespace sdcb {
namespace {

// Derivative-free steps against the parameterization's shear.
constexpr int kShearSteps = 3;
// Gauss-Newton steps of the closest-point search after them.
constexpr int kClosestPointIterations = 8;

}  // namespace

Eigen::VectorXd FlatToSurfaceDistances(
    const SurfaceSampler& surface, const SurfaceSamples& samples,
    const std::vector<int>& faces, const std::vector<Eigen::Vector3d>& weights,
    const Eigen::MatrixX3d& directions, const Eigen::MatrixX3d& points,
    double good_enough, int64_t* evaluations) {
  const SphereTriangulation& pattern = samples.pattern;
  const Eigen::Index total = points.rows();
  const auto flat_at = [&](int f, const Eigen::Vector3d& w) {
    const auto& t = pattern.face(f);
    return Eigen::Vector3d(w[0] * samples.positions[t[0]] +
                           w[1] * samples.positions[t[1]] +
                           w[2] * samples.positions[t[2]]);
  };
  Eigen::MatrixX3d flat(total, 3);
  Eigen::VectorXd distance(total);
  tbb::parallel_for(Eigen::Index{0}, total, [&](Eigen::Index r) {
    flat.row(r) = flat_at(faces[r], weights[r]).transpose();
    distance[r] = (flat.row(r) - points.row(r)).norm();
  });
  std::vector<Eigen::Index> far;
  for (Eigen::Index r = 0; r < total; ++r) {
    if (distance[r] > good_enough) far.push_back(r);
  }

  // Shear steps, from the weights and the surface point at them.
  std::vector<Eigen::Vector3d> w(far.size()), at(far.size());
  for (size_t j = 0; j < far.size(); ++j) {
    w[j] = weights[far[j]];
    at[j] = points.row(far[j]).transpose();
  }
  std::vector<size_t> active(far.size());
  for (size_t j = 0; j < far.size(); ++j) active[j] = j;
  for (int step = 0; step < kShearSteps && !active.empty(); ++step) {
    const Eigen::Index m = static_cast<Eigen::Index>(active.size());
    Eigen::MatrixX3d moved(m, 3), image;
    tbb::parallel_for(Eigen::Index{0}, m, [&](Eigen::Index k) {
      const size_t j = active[k];
      const auto& t = pattern.face(faces[far[j]]);
      const Eigen::Vector3d& pa = samples.positions[t[0]];
      Eigen::Matrix<double, 3, 2> edges;
      edges.col(0) = samples.positions[t[1]] - pa;
      edges.col(1) = samples.positions[t[2]] - pa;
      const Eigen::Vector3d off = at[j] - flat.row(far[j]).transpose();
      const Eigen::Vector2d d =
          (edges.transpose() * edges).ldlt().solve(-edges.transpose() * off);
      if (d.allFinite()) w[j] += Eigen::Vector3d(-d[0] - d[1], d[0], d[1]);
      moved.row(k) =
          (w[j][0] * pattern.vertex(t[0]) + w[j][1] * pattern.vertex(t[1]) +
           w[j][2] * pattern.vertex(t[2]))
              .normalized()
              .transpose();
    });
    surface.Sample(moved, &image, nullptr);
    *evaluations += m;
    std::vector<size_t> next;
    for (Eigen::Index k = 0; k < m; ++k) {
      const size_t j = active[k];
      at[j] = image.row(k).transpose();
      const Eigen::Index r = far[j];
      distance[r] = std::min(distance[r], (flat.row(r) - image.row(k)).norm());
      if (distance[r] > good_enough) next.push_back(j);
    }
    active = std::move(next);
  }

  // What is still above: a closest-point search from the domain point.
  std::vector<Eigen::Index> rest;
  for (Eigen::Index r : far) {
    if (distance[r] > good_enough) rest.push_back(r);
  }
  if (!rest.empty()) {
    const Eigen::Index n = static_cast<Eigen::Index>(rest.size());
    Eigen::MatrixX3d x(n, 3), u(n, 3);
    for (Eigen::Index j = 0; j < n; ++j) {
      x.row(j) = flat.row(rest[j]);
      u.row(j) = directions.row(rest[j]);
    }
    const Eigen::VectorXd found = ClosestSurfacePoints(
        surface, x, kClosestPointIterations, &u, evaluations, good_enough);
    for (Eigen::Index j = 0; j < n; ++j) {
      distance[rest[j]] = std::min(distance[rest[j]], found[j]);
    }
  }
  return distance;
}

}  // namespace sdcb
