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

// The most samples either side takes: the steps grow beyond the asked ones
// to keep to it (a hostile boundary of many long edges; a fit's boundary
// takes a few thousand).
constexpr double kMaxSamples = 250000;

// The trims' arcs sampled at their two ends and evenly between them (at
// least min_samples_per_edge points, no farther apart than max_step
// radians, or than their length over kMaxSamples): the sphere points, loop by
// loop (`loop_start`: where each begins, and the end), and each sample's edge
// and fraction along it.
struct TrimSamples {
  Eigen::MatrixX3d sphere;
  std::vector<int> loop_start;
  std::vector<Eigen::Index> edge;
  std::vector<double> fraction;
};

TrimSamples SampleTrims(const std::vector<TrimLoop>& trims, double max_step,
                        int min_samples_per_edge) {
  double length = 0;
  for (const TrimLoop& trim : trims) {
    const Eigen::MatrixX3d& u = trim.points;
    for (Eigen::Index i = 0; i < u.rows(); ++i) {
      const Eigen::Vector3d a = u.row(i), b = u.row((i + 1) % u.rows());
      length += std::atan2(a.cross(b).norm(), a.dot(b));
    }
  }
  max_step = std::max(max_step, length / kMaxSamples);
  std::vector<Eigen::Vector3d> sphere;
  TrimSamples out;
  for (const TrimLoop& trim : trims) {
    const Eigen::MatrixX3d& u = trim.points;
    out.loop_start.push_back(static_cast<int>(sphere.size()));
    const Eigen::Index n = u.rows();
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::Vector3d a = u.row(i), b = u.row((i + 1) % n);
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
        out.edge.push_back(i);
        out.fraction.push_back(t);
      }
    }
  }
  out.loop_start.push_back(static_cast<int>(sphere.size()));
  out.sphere.resize(static_cast<Eigen::Index>(sphere.size()), 3);
  for (size_t i = 0; i < sphere.size(); ++i) {
    out.sphere.row(static_cast<Eigen::Index>(i)) = sphere[i].transpose();
  }
  return out;
}

Status CheckArguments(double length_unit, double max_step,
                      int min_samples_per_edge) {
  if (!(length_unit > 0) || !(max_step > 0) || min_samples_per_edge < 2) {
    return InvalidArgumentError(
        "boundary deviation: the length unit and the step must be > 0 and "
        "an edge needs at least 2 samples");
  }
  return Status::Ok();
}

// F at the samples, and the closed polylines through them, loop by loop.
StatusOr<Eigen::MatrixX3d> TrimImages(const SphericalSpline& surface,
                                      const TrimSamples& samples,
                                      std::vector<Segment>* segments) {
  const Eigen::MatrixX3d image = surface.EvaluateMany(samples.sphere);
  for (Eigen::Index i = 0; i < image.rows(); ++i) {
    if (!image.row(i).allFinite()) {
      return InvalidInputError(
          "boundary deviation: the surface is undefined on a trim");
    }
  }
  for (size_t l = 0; l + 1 < samples.loop_start.size(); ++l) {
    const int begin = samples.loop_start[l], end = samples.loop_start[l + 1];
    for (int i = begin; i < end; ++i) {
      AddSegment(image.row(i), image.row(i + 1 < end ? i + 1 : begin),
                 segments);
    }
  }
  return image;
}

// Both ways between the trims' images and the part's boundary segments,
// the part's side at `mesh_points`.
BoundaryDeviation Measure(const Eigen::MatrixX3d& image,
                          const std::vector<Segment>& surface_segments,
                          const std::vector<Segment>& mesh_segments,
                          const Eigen::MatrixX3d& mesh_points,
                          double length_unit) {
  BoundaryDeviation out;
  out.samples = image.rows();
  const double to_percent = 100.0 / length_unit;
  out.surface_to_mesh_max_percent =
      to_percent * LargestDistance(mesh_segments, image);
  out.mesh_to_surface_max_percent =
      to_percent * LargestDistance(surface_segments, mesh_points);
  return out;
}

}  // namespace

StatusOr<BoundaryDeviation> MeasureBoundaryDeviation(
    const SphericalSpline& surface, const std::vector<TrimLoop>& trims,
    const std::vector<Eigen::MatrixX3d>& loops, double length_unit,
    double max_step, int min_samples_per_edge) {
  SDCB_RETURN_IF_ERROR(
      CheckArguments(length_unit, max_step, min_samples_per_edge));
  if (loops.size() != trims.size()) {
    return InvalidArgumentError(
        "boundary deviation: a mesh loop is needed per trim loop");
  }
  for (size_t l = 0; l < trims.size(); ++l) {
    if (loops[l].rows() != trims[l].points.rows() ||
        trims[l].points.rows() < 2) {
      return InvalidArgumentError("boundary deviation: loop " +
                                  std::to_string(l + 1) +
                                  " has a different number of points");
    }
  }
  const TrimSamples samples =
      SampleTrims(trims, max_step, min_samples_per_edge);
  std::vector<Segment> surface_segments, mesh_segments;
  SDCB_ASSIGN_OR_RETURN(const Eigen::MatrixX3d image,
                        TrimImages(surface, samples, &surface_segments));
  // The part's boundary at the same fractions of each edge as the arc's.
  Eigen::MatrixX3d mesh_points(samples.sphere.rows(), 3);
  for (size_t l = 0; l < trims.size(); ++l) {
    const Eigen::MatrixX3d& x = loops[l];
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
      AddSegment(x.row(i), x.row((i + 1) % x.rows()), &mesh_segments);
    }
    for (int k = samples.loop_start[l]; k < samples.loop_start[l + 1]; ++k) {
      const Eigen::Index e = samples.edge[k];
      const double t = samples.fraction[k];
      mesh_points.row(k) = (1 - t) * x.row(e) + t * x.row((e + 1) % x.rows());
    }
  }
  return Measure(image, surface_segments, mesh_segments, mesh_points,
                 length_unit);
}

StatusOr<BoundaryDeviation> MeasureBoundaryDeviation(
    const SphericalSpline& surface, const std::vector<TrimLoop>& trims,
    const Eigen::MatrixX3d& vertices, const Eigen::MatrixX2i& edges,
    double length_unit, double max_step, double mesh_step) {
  SDCB_RETURN_IF_ERROR(CheckArguments(length_unit, max_step, 2));
  if (!(mesh_step > 0)) {
    return InvalidArgumentError("boundary deviation: the step must be > 0");
  }
  if (edges.size() > 0 &&
      (edges.minCoeff() < 0 || edges.maxCoeff() >= vertices.rows())) {
    return InvalidArgumentError(
        "boundary deviation: an edge names a vertex out of range");
  }
  for (const TrimLoop& trim : trims) {
    if (trim.points.rows() < 2) {
      return InvalidArgumentError(
          "boundary deviation: a trim loop has fewer than 2 points");
    }
  }
  const TrimSamples samples = SampleTrims(trims, max_step, 4);
  std::vector<Segment> surface_segments, mesh_segments;
  SDCB_ASSIGN_OR_RETURN(const Eigen::MatrixX3d image,
                        TrimImages(surface, samples, &surface_segments));
  // Each boundary edge at its two ends and evenly between them, no farther
  // apart than mesh_step (or the edges' length over kMaxSamples).
  double length = 0;
  for (Eigen::Index e = 0; e < edges.rows(); ++e) {
    length += (vertices.row(edges(e, 1)) - vertices.row(edges(e, 0))).norm();
  }
  mesh_step = std::max(mesh_step, length / kMaxSamples);
  std::vector<Eigen::Vector3d> points;
  for (Eigen::Index e = 0; e < edges.rows(); ++e) {
    const Eigen::Vector3d a = vertices.row(edges(e, 0)),
                          b = vertices.row(edges(e, 1));
    AddSegment(a, b, &mesh_segments);
    const int steps =
        std::max(1, static_cast<int>(std::ceil((b - a).norm() / mesh_step)));
    for (int k = 0; k <= steps; ++k) {
      const double t = static_cast<double>(k) / steps;
      points.push_back((1 - t) * a + t * b);
    }
  }
  Eigen::MatrixX3d mesh_points(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t i = 0; i < points.size(); ++i) {
    mesh_points.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
  }
  return Measure(image, surface_segments, mesh_segments, mesh_points,
                 length_unit);
}

}  // namespace sdcb
