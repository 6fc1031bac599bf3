// Conversions between TriangleMesh and CGAL's Surface_mesh, for the stages
// that use CGAL Polygon_mesh_processing (self-intersections, repair, hole
// filling), and the one hole filler both repair and FillHoles call.
#ifndef SDCB_CORE_MESH_CGAL_MESH_H_
#define SDCB_CORE_MESH_CGAL_MESH_H_

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include <optional>
#include <vector>

#include "sdcb/core/mesh/hole_filling.h"
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

// How FillCgalHole fills one hole; each step falls back to the next.
struct CgalHoleFillOptions {
  // Try a 2D constrained Delaunay triangulation in the hole's best-fit plane
  // first (CGAL: when the loop is within a quarter of its bounding box's
  // height of that plane), then the search over the 3D Delaunay
  // triangulation of the loop's vertices.
  bool use_2d_delaunay = false;
  // When those find nothing: CGAL's search over all triangulations, O(n^3)
  // time and O(n^2) memory in the loop's n edges; only for n at most this.
  int max_cubic_search_edges = 1 << 30;
  // When nothing else triangulates the hole: a fan from a new vertex at the
  // loop's centroid (always closes it combinatorially).
  bool fan_fallback = false;
  // False skips CGAL's triangulations (straight to the fan, if allowed):
  // how the tests reach the fan, which CGAL's searches rarely leave to it.
  bool cgal_triangulation = true;
  // Split the patch's triangles to the density of the loop's edges
  // (CGAL's refine, density_control_factor sqrt(2)).
  bool refine = true;
  // Then fair the refined patch (CGAL's fair: a bi-Laplacian system,
  // tangent-continuous to the surrounding faces) when it has at most this
  // many new vertices (fairing solves a sparse system in them); 0: never.
  int max_fair_vertices = 0;
};

// Fills the hole whose border half-edge (face() null) is `border`: the
// faces and vertices it adds are appended to `mesh`; no face or vertex that
// was there before changes. Returns the method that filled it, or
// std::nullopt when none did (the mesh as it was, though a refused fan
// leaves removed elements that Surface_mesh's iterators skip).
// Deterministic. CGAL may throw on a violated precondition; callers catch.
std::optional<HoleFillMethod> FillCgalHole(CgalMesh::Halfedge_index border,
                                           const CgalHoleFillOptions& options,
                                           CgalMesh* mesh, int* added_faces,
                                           int* added_vertices);

}  // namespace sdcb

#endif  // SDCB_CORE_MESH_CGAL_MESH_H_
