// The central projection of a star-shaped mesh onto the sphere: every vertex
// v to (v - c) / |v - c| for the centroid c of its vertices (mirrored in x
// for a mesh whose faces all point inward, so that its sphere triangles are
// counter-clockwise in the faces' order, as the fit's parameterization
// makes them for any mesh). When every
// triangle's plane has c strictly on its inner side (a convex solid, or any
// solid whose faces all see c), the sphere triangles are all positively
// oriented and tile the sphere once, and each planar face of the solid maps
// to the sphere by one projective map, the same for all its triangles: a
// feature edge between two corners is then an arc of the great circle
// through it and c, and a face is flat in the spline's parameter wherever
// the spline reproduces the projection (core/knots/feature_knots.h).
#ifndef SDCB_CORE_PARAM_CENTRAL_PROJECTION_H_
#define SDCB_CORE_PARAM_CENTRAL_PROJECTION_H_

#include <Eigen/Core>
#include <optional>

#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

// #V by 3 unit vectors, or nothing when some triangle does not see the
// centroid from inside (its plane's distance to the centroid, along its
// normal, at most 1e-9 of the mesh's size; the normals all out or all in),
// or a vertex is at it.
std::optional<Eigen::MatrixX3d> CentralProjection(const TriangleMesh& mesh);

}  // namespace sdcb

#endif  // SDCB_CORE_PARAM_CENTRAL_PROJECTION_H_
