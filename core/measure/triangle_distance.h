// A point and a flat triangle in R^3: the triangle's closest point, the
// distance, and the barycentric coordinates of a point of the triangle
// (the one place these are computed; the measurements of
// core/measure/surface_deviation.h, the export certificate and the cage's
// deviation call them).
#ifndef SDCB_CORE_MEASURE_TRIANGLE_DISTANCE_H_
#define SDCB_CORE_MEASURE_TRIANGLE_DISTANCE_H_

#include <Eigen/Core>

namespace sdcb {

// The point of triangle (a, b, c) closest to p (Voronoi regions of the
// vertices, edges and face). Degenerate triangles (collinear or coincident
// corners) are handled: the result is then the closest point on the segments.
Eigen::Vector3d ClosestPointOnTriangle(const Eigen::Vector3d& p,
                                       const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c);

inline double PointTriangleDistance(const Eigen::Vector3d& p,
                                    const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c) {
  return (p - ClosestPointOnTriangle(p, a, b, c)).norm();
}

// Barycentric coordinates (u, v, w), u + v + w = 1, of q's projection onto
// the plane of (a, b, c) (q = u a + v b + w c for q in that plane), by the
// normal equations of q - a = v (b - a) + w (c - a). Not clamped: outside
// the triangle some are negative. (1/3, 1/3, 1/3) where the triangle is
// degenerate (its edges' Gram determinant not > 0).
Eigen::Vector3d TriangleCoordinates(const Eigen::Vector3d& q,
                                    const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c);

// TriangleCoordinates with v clamped into [0, 1] and then w into
// [0, 1 - v] (u = 1 - v - w): the coordinates of a point of the triangle,
// for q a closest point of the triangle that rounding may leave just
// outside.
Eigen::Vector3d ClampedTriangleCoordinates(const Eigen::Vector3d& q,
                                           const Eigen::Vector3d& a,
                                           const Eigen::Vector3d& b,
                                           const Eigen::Vector3d& c);

}  // namespace sdcb

#endif  // SDCB_CORE_MEASURE_TRIANGLE_DISTANCE_H_
