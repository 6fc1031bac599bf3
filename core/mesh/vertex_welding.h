// Vertices at exactly equal positions made one. Many OBJ, PLY and glTF
// writers split a vertex wherever its texture coordinate or normal changes,
// so a closed surface arrives as open pieces whose boundaries lie on each
// other (a cube of 24 vertices is six open quads). The one kernel behind
// `sdcb check`'s duplicate-vertex count, RepairMesh's first step and the
// intake's seam weld (docs/INTAKE.md).
#ifndef SDCB_CORE_MESH_VERTEX_WELDING_H_
#define SDCB_CORE_MESH_VERTEX_WELDING_H_

#include <string>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

// @param[in] vertices  #V by 3 positions.
// @return #V entries: the number of each vertex's position among the
//   distinct positions, numbered in order of first appearance (vertex 0 is
//   0; a vertex at a position not seen before gets the next number).
//   Positions are equal when all three coordinates compare equal (-0 == +0),
//   like CGAL's Less_xyz_3. O(#V log #V), the sort in parallel.
std::vector<int> EqualPositionNumbers(const Eigen::MatrixX3d& vertices);

struct WeldedMesh {
  // The distinct positions in order of first appearance; the input's faces
  // in their order with their corners renumbered (a face whose corners were
  // at equal positions then uses a vertex twice).
  TriangleMesh mesh;
  // #V of the input entries: the row of `mesh` each input vertex became.
  std::vector<int> new_vertex;

  // Input vertices merged into an earlier one.
  int merged_vertices() const {
    return static_cast<int>(new_vertex.size()) - mesh.num_vertices();
  }
};

// Merges every set of vertices at equal positions (EqualPositionNumbers)
// into one. A mesh without equal positions comes back bit for bit, with
// the identity map.
WeldedMesh WeldEqualPositions(const TriangleMesh& mesh);

// What WeldSeams did.
struct SeamWeldReport {
  // Vertices merged into an earlier one at the same position (0 when none
  // were, or when the weld was declined).
  int merged_vertices = 0;
  // Vertices at the position of an earlier one left apart because welding
  // would have made the mesh worse; `declined_because` says how, e.g.
  // "merging them would make 2 edges non-manifold".
  int declined_vertices = 0;
  std::string declined_because;

  // "merged 16 vertices split at equal positions (UV or normal seams)";
  // empty when nothing was merged.
  std::string Describe() const;
};

// The intake's rule, the same for `check` and `fit` before the parts are
// split: when vertices at equal positions exist and welding them all turns
// boundary edges into interior edges without adding any non-manifold edge,
// non-manifold vertex or inconsistently oriented edge, returns the welded
// mesh; otherwise `mesh` unchanged with the identity map, and, when the
// weld would have closed boundary edges but made the mesh worse, how in
// `report`. A weld that closes no boundary edge (a closed mesh's stray
// copies, copies no triangle uses) is neither done nor reported, so closed
// meshes always come back as they are. kInvalidInput for indices out of
// range.
StatusOr<WeldedMesh> WeldSeams(const TriangleMesh& mesh,
                               SeamWeldReport* report);

}  // namespace sdcb

#endif  // SDCB_CORE_MESH_VERTEX_WELDING_H_
