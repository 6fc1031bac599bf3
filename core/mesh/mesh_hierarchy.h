// A progressive-mesh hierarchy of a closed genus-0 triangle mesh (Hoppe's
// progressive meshes, as the paper's Sec. 4.3 uses for coarse-to-fine
// parameterization): a sequence of half-edge collapses from the input down
// to a small base mesh, recorded so that they can be undone one by one
// (vertex splits) in reverse order.
//
// Half-edge collapse v -> u removes vertex v and the two faces on edge (v,u)
// and re-points v's other faces to u; the kept vertex stays at its input
// position. A collapse is taken only if it keeps the surface a closed
// manifold (the link condition) and does not turn any re-pointed face by
// more than `max_normal_turn_degrees` in 3D.
#ifndef SDCB_CORE_MESH_MESH_HIERARCHY_H_
#define SDCB_CORE_MESH_MESH_HIERARCHY_H_

#include <Eigen/Core>
#include <array>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

struct MeshHierarchyOptions {
  // Stop once the mesh has this many vertices (at least 4) or no collapse is
  // allowed any more.
  int base_vertices = 200;
  // Largest rotation of a face normal a collapse may cause.
  double max_normal_turn_degrees = 60.0;
  // A collapse may not make a face worse than this quality (4 sqrt(3) area /
  // sum of squared edges; 1 = equilateral), unless it already was.
  double min_triangle_quality = 0.3;
  // A vertex with more triangles than this around it is never removed (it
  // stays in the base mesh). Keeps the work per collapse bounded: without
  // it, a fan of n triangles around one vertex (a CAD cylinder cap) costs
  // O(n^2) time and memory.
  int max_removed_valence = 64;
};

// One half-edge collapse `removed` -> `kept`.
struct HalfEdgeCollapse {
  int removed = -1;
  int kept = -1;
  // The removed vertex's neighbors counter-clockwise (seen from outside),
  // starting with `kept`, as they were just before the collapse.
  std::vector<int> link;
  // The two faces on edge (removed, kept) that the collapse deleted.
  std::array<int, 2> deleted_faces = {-1, -1};
  // Faces in which the collapse replaced `removed` by `kept`.
  std::vector<int> repointed_faces;
};

struct MeshHierarchy {
  // #F by 3: the input's faces after all collapses (deleted faces keep
  // their last corners; see face_alive).
  Eigen::MatrixX3i faces;
  std::vector<bool> face_alive;    // #F, alive in the base mesh
  std::vector<bool> vertex_alive;  // #V, alive in the base mesh
  // In the order applied; undo them from the back.
  std::vector<HalfEdgeCollapse> collapses;
};

// Builds the hierarchy of `mesh`, which must be a closed, manifold,
// consistently oriented genus-0 mesh (RequireClosedGenusZero). Collapses are
// chosen shortest edge first, ties broken by vertex indices, so the result
// is deterministic. Time O(F log F) for bounded max_removed_valence, whatever
// the valences in the input.
StatusOr<MeshHierarchy> BuildMeshHierarchy(
    const TriangleMesh& mesh, const MeshHierarchyOptions& options = {});

// Undoes `collapse` (a vertex split) on `faces`/`face_alive`/`vertex_alive`,
// which must be in the state right after that collapse.
void UndoCollapse(const HalfEdgeCollapse& collapse, Eigen::MatrixX3i* faces,
                  std::vector<bool>* face_alive,
                  std::vector<bool>* vertex_alive);

}  // namespace sdcb

#endif  // SDCB_CORE_MESH_MESH_HIERARCHY_H_
