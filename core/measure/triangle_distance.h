// Euclidean distance from a point to a (flat, closed) triangle in R^3.
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

}  // namespace sdcb

#endif  // SDCB_CORE_MEASURE_TRIANGLE_DISTANCE_H_
