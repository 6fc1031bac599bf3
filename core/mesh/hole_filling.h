// Closes an open genus-0 part for the spherical fit: every boundary loop
// filled with a fair patch (CGAL's triangulate_refine_and_fair_hole), so the
// result is a closed genus-0 mesh the sphere map takes. The fit weights the
// fill's triangles so that they only keep the spline smooth, and the part's
// boundary loops become its trims (core/spline/model.h).
#ifndef SDCB_CORE_MESH_HOLE_FILLING_H_
#define SDCB_CORE_MESH_HOLE_FILLING_H_

#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

// How a hole was filled, best first: the triangulation refined to the
// density of the loop's edges and faired (CGAL's
// triangulate_refine_and_fair_hole); refined but not faired (the patch was
// too large to fair quickly, or fairing failed); only triangulated; a fan
// from a new vertex at the loop's centroid (when CGAL's triangulations find
// nothing; closed, but possibly folded).
enum class HoleFillMethod { kFaired, kRefined, kTriangulated, kFan };

// "faired", "refined", "triangulated", "fan".
const char* HoleFillMethodName(HoleFillMethod method);

struct FilledMesh {
  // Closed, manifold, genus 0, consistently oriented: the part's vertices
  // first (same rows), then the fill's new vertices; the part's faces first
  // (same rows), then the fill's.
  TriangleMesh mesh;
  int input_vertices = 0;
  int input_faces = 0;
  // Per boundary loop of the part, its vertex rows in the direction of its
  // boundary half-edges: the part's triangles lie on the LEFT of each edge
  // (a face (a, b, c) with boundary edge a-b gives ... a, b ...). Loops in
  // the order of their smallest vertex row, each starting at that row.
  std::vector<std::vector<int>> boundary_loops;
  // Per boundary loop (same order), how its hole was filled.
  std::vector<HoleFillMethod> fill_methods;

  // The part alone: the first input_vertices rows and input_faces faces.
  TriangleMesh Part() const;
};

// Fills every hole of `part`, an open, manifold, consistently oriented
// genus-0 mesh (sdcb::ReportPart says fittable). A closed part comes back
// unchanged with no loops. kInvalidInput with one sentence when the filling
// fails or its result is not a closed genus-0 mesh. Deterministic.
// Each hole: a 2D constrained Delaunay triangulation when the loop is near a
// plane, else CGAL's 3D Delaunay search (its cubic search only for loops of
// at most 300 edges), else a centroid fan; then refined; then faired when
// the refined patch has at most 20,000 new vertices.
StatusOr<FilledMesh> FillHoles(const TriangleMesh& part);

}  // namespace sdcb

#endif  // SDCB_CORE_MESH_HOLE_FILLING_H_
