// Conversions between TriangleMesh and CGAL's Surface_mesh, for the stages
// that use CGAL Polygon_mesh_processing (self-intersections, repair).
#ifndef SDCB_CORE_MESH_CGAL_MESH_H_
#define SDCB_CORE_MESH_CGAL_MESH_H_

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

using CgalKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalMesh = CGAL::Surface_mesh<CgalKernel::Point_3>;

// Builds `out` with the same vertices (same indices) and faces (same
// indices, same orientation). False, leaving `out` empty, when the
// triangles do not form an oriented 2-manifold (possibly with boundary),
// which a Surface_mesh cannot hold. Indices must be in range.
bool ToCgalMesh(const TriangleMesh& mesh, CgalMesh* out);

// The vertices and faces of `mesh` (which may have removed elements),
// renumbered densely in the mesh's order.
TriangleMesh FromCgalMesh(const CgalMesh& mesh);

}  // namespace sdcb

#endif  // SDCB_CORE_MESH_CGAL_MESH_H_
