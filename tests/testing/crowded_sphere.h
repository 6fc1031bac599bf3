// A strongly non-uniform triangulation of the unit sphere for tests and
// benchmarks of point location: an icosphere whose vertices are moved by the
// Moebius map that scales the stereographic plane (projected from the north
// pole (0, 0, 1)) by `scale` < 1, so they crowd towards the south pole. The
// map is conformal; it shrinks lengths at the south pole by `scale` and
// stretches them at the north pole by 1 / `scale`, so triangle areas vary by
// about scale^-4 (10^4 for 0.1), like the sphere map of a mesh with thin or
// detailed parts.
#ifndef SDCB_TESTS_TESTING_CROWDED_SPHERE_H_
#define SDCB_TESTS_TESTING_CROWDED_SPHERE_H_

#include <Eigen/Core>

#include "sdcb/core/mesh/icosphere.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb::testing {

// MakeIcosphere(subdivisions) with every vertex moved as above (unit
// vectors, same faces, counter-clockwise seen from outside: the map keeps
// orientation).
inline TriangleMesh CrowdedIcosphere(int subdivisions, double scale) {
  TriangleMesh m = MakeIcosphere(subdivisions);
  for (Eigen::Index v = 0; v < m.vertices.rows(); ++v) {
    const Eigen::Vector3d p = m.vertices.row(v).normalized();
    if (p.z() >= 1.0) continue;  // the north pole stays
    // Stereographic coordinates q = (x, y) / (1 - z), scaled, and back:
    // z = (|q|^2 - 1) / (|q|^2 + 1), (x, y) = 2 q / (|q|^2 + 1).
    const Eigen::Vector2d q =
        scale * Eigen::Vector2d(p.x(), p.y()) / (1 - p.z());
    const double r2 = q.squaredNorm();
    m.vertices.row(v) =
        Eigen::Vector3d(2 * q.x(), 2 * q.y(), r2 - 1).normalized().transpose();
  }
  return m;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_CROWDED_SPHERE_H_
