#include "sdcb/core/measure/boundary_deviation.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace sdcb {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using Iterator = std::vector<Segment>::const_iterator;
using Primitive = CGAL::AABB_segment_primitive<Kernel, Iterator>;
using SegmentTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Point ToPoint(const Eigen::Vector3d& v) { return Point(v.x(), v.y(), v.z()); }

// The largest distance from a row of `points` to `segments` (none of zero
// length).
double LargestDistance(const std::vector<Segment>& segments,
                       const Eigen::MatrixX3d& points) {
  if (segments.empty() || points.rows() == 0) return 0.0;
  SegmentTree tree(segments.begin(), segments.end());
  tree.accelerate_distance_queries();
  const double squared = tbb::parallel_reduce(
      tbb::blocked_range<Eigen::Index>(0, points.rows(), 512), 0.0,
      [&](const tbb::blocked_range<Eigen::Index>& range, double best) {
        for (Eigen::Index i = range.begin(); i < range.end(); ++i) {
          best = std::max(best, CGAL::to_double(tree.squared_distance(
                                    ToPoint(points.row(i).transpose()))));
        }
        return best;
      },
      [](double a, double b) { return std::max(a, b); });
  return std::sqrt(squared);
}

void AddSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                std::vector<Segment>* segments) {
  if (a != b) segments->emplace_back(ToPoint(a), ToPoint(b));
}

}  // namespace

StatusOr<BoundaryDeviation> MeasureBoundaryDeviation(
    const SphericalSpline& surface, const std::vector<TrimLoop>& trims,
    const std::vector<Eigen::MatrixX3d>& loops, double length_unit,
    double max_step, int min_samples_per_edge) {
  if (!(length_unit > 0) || !(max_step > 0) || min_samples_per_edge < 2) {
    return InvalidArgumentError(
        "boundary deviation: the length unit and the step must be > 0 and "
        "an edge needs at least 2 samples");
  }
  if (loops.size() != trims.size()) {
    return InvalidArgumentError(
        "boundary deviation: a mesh loop is needed per trim loop");
  }
  // Per edge of every loop: its samples on the sphere (the arc) and on the
  // mesh (the segment), at the same fractions of the edge.
  std::vector<Eigen::Vector3d> sphere, on_mesh;
  std::vector<int> loop_start;
  for (size_t l = 0; l < trims.size(); ++l) {
    const Eigen::MatrixX3d& u = trims[l].points;
    const Eigen::MatrixX3d& x = loops[l];
    if (x.rows() != u.rows() || u.rows() < 2) {
      return InvalidArgumentError("boundary deviation: loop " +
                                  std::to_string(l + 1) +
                                  " has a different number of points");
    }
    loop_start.push_back(static_cast<int>(sphere.size()));
    const Eigen::Index n = u.rows();
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::Vector3d a = u.row(i), b = u.row((i + 1) % n);
      const Eigen::Vector3d xa = x.row(i), xb = x.row((i + 1) % n);
      const double angle = std::atan2(a.cross(b).norm(), a.dot(b));
      const int steps = std::max(min_samples_per_edge - 1,
                                 static_cast<int>(std::ceil(angle / max_step)));
      // The edge's samples but its last (the next edge's first).
      for (int k = 0; k < steps; ++k) {
        const double t = static_cast<double>(k) / steps;
        const double s = std::sin(angle);
        const Eigen::Vector3d p =
            s > 0 ? Eigen::Vector3d((std::sin((1 - t) * angle) * a +
                                     std::sin(t * angle) * b) /
                                    s)
                  : a;
        sphere.push_back(p.normalized());
        on_mesh.push_back((1 - t) * xa + t * xb);
      }
    }
  }
  loop_start.push_back(static_cast<int>(sphere.size()));
  const Eigen::Index ns = static_cast<Eigen::Index>(sphere.size());
  Eigen::MatrixX3d sphere_points(ns, 3), mesh_points(ns, 3);
  for (Eigen::Index i = 0; i < ns; ++i) {
    sphere_points.row(i) = sphere[i].transpose();
    mesh_points.row(i) = on_mesh[i].transpose();
  }
  const Eigen::MatrixX3d image = surface.EvaluateMany(sphere_points);
  for (Eigen::Index i = 0; i < ns; ++i) {
    if (!image.row(i).allFinite()) {
      return InvalidInputError(
          "boundary deviation: the surface is undefined on a trim");
    }
  }
  // Closed polylines: the part's boundary and the F samples.
  std::vector<Segment> mesh_segments, surface_segments;
  for (size_t l = 0; l < trims.size(); ++l) {
    const Eigen::MatrixX3d& x = loops[l];
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
      AddSegment(x.row(i), x.row((i + 1) % x.rows()), &mesh_segments);
    }
    const int begin = loop_start[l], end = loop_start[l + 1];
    for (int i = begin; i < end; ++i) {
      AddSegment(image.row(i), image.row(i + 1 < end ? i + 1 : begin),
                 &surface_segments);
    }
  }
  BoundaryDeviation out;
  out.samples = ns;
  const double to_percent = 100.0 / length_unit;
  out.surface_to_mesh_max_percent =
      to_percent * LargestDistance(mesh_segments, image);
  out.mesh_to_surface_max_percent =
      to_percent * LargestDistance(surface_segments, mesh_points);
  return out;
}

}  // namespace sdcb
