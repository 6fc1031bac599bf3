// Repairs the common defects of meshes from scanners and other tools so that
// they become closed genus-0 surfaces (`sdcb check --repair`, `sdcb fit
// --repair`), with CGAL Polygon_mesh_processing, in this order:
//  1. merge vertices at exactly equal positions (STL-style soups, seams);
//  2. drop faces that use a vertex twice and faces that repeat another face
//     (same corners, either orientation);
//  3. orient the faces consistently (CGAL's orient_polygon_soup);
//  4. remove zero-area triangles (edge collapses and flips);
//  5. fill small holes (triangulate, then refine to the surrounding density);
//  6. orient outward; drop vertices no face uses.
// The result is checked like any input (RequireClosedGenusZero); what cannot
// be made a closed genus-0 mesh (higher genus, several components, large
// holes, non-manifold edges left after merging) is refused.
#ifndef SDCB_CORE_MESH_MESH_REPAIR_H_
#define SDCB_CORE_MESH_MESH_REPAIR_H_

#include <string>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

struct MeshRepairOptions {
  // A hole (boundary loop) is filled if it has at most this many edges ...
  int max_hole_edges = 200;
  // ... and its vertices span at most this percent of the largest side of
  // the mesh's bounding box (a cut-off cap is not a small hole).
  double max_hole_percent = 25.0;
};

// What RepairMesh changed; all zero for a mesh that needed nothing.
struct MeshRepairReport {
  int merged_vertices = 0;  // vertices merged into an equal earlier one
  int dropped_degenerate_faces = 0;  // repeated corner or zero area
  int dropped_duplicate_faces = 0;
  int reoriented_faces = 0;  // faces whose orientation was reversed
  int filled_holes = 0;
  int added_faces = 0;     // by hole filling
  int added_vertices = 0;  // by hole filling
  int dropped_unreferenced_vertices = 0;

  bool changed() const;
  // E.g. "merged 12 duplicate vertices, filled 2 holes with 14 triangles";
  // "nothing to repair" when unchanged.
  std::string Describe() const;
};

// The repaired mesh (vertices renumbered). Fails with kUnsupported when the
// result is not a closed genus-0 mesh: "cannot be repaired into a closed
// genus-0 mesh: <why>"; kInvalidInput for indices out of range.
StatusOr<TriangleMesh> RepairMesh(const TriangleMesh& mesh,
                                  const MeshRepairOptions& options,
                                  MeshRepairReport* report);

}  // namespace sdcb

#endif  // SDCB_CORE_MESH_MESH_REPAIR_H_
