// Combinatorial and geometric sanity of a triangle mesh: what `sdcb check`
// reports and what every stage that needs a closed genus-0 surface checks.
#ifndef SDCB_CORE_MESH_MESH_TOPOLOGY_H_
#define SDCB_CORE_MESH_MESH_TOPOLOGY_H_

#include <Eigen/Core>
#include <string>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

struct MeshTopologyReport {
  int vertices = 0;               // all vertices in the file
  int faces = 0;                  // triangles (after triangulating polygons)
  int edges = 0;                  // distinct undirected edges
  int boundary_edges = 0;         // edges with exactly one incident triangle
  int boundary_loops = 0;         // closed chains of boundary edges
  int non_manifold_edges = 0;     // edges with three or more incident triangles
  int non_manifold_vertices = 0;  // vertices whose triangles form several fans
  int inconsistently_oriented_edges =
      0;                          // interior edges used twice the same way
  int unreferenced_vertices = 0;  // vertices no triangle uses
  int duplicate_vertices =
      0;  // vertices at exactly the position of an earlier one
  int degenerate_faces = 0;  // zero-area triangles (exact collinearity test)
  int components = 0;        // connected components of the triangles
  // V - E + F over the referenced vertices.
  int euler_characteristic = 0;
  // Total genus sum_c (2 - chi_c - b_c) / 2; meaningful for manifold meshes.
  int genus = 0;
  // True only for a closed, manifold, consistently oriented, single-component
  // genus-0 mesh without degenerate faces or unreferenced vertices.
  bool ok = false;
};

// Computes the report. Never fails on a well-formed TriangleMesh (indices in
// range); the indices are checked and a bad one gives kInvalidInput.
StatusOr<MeshTopologyReport> AnalyzeMeshTopology(const TriangleMesh& mesh);

// The edges with exactly one incident triangle, each as that triangle's
// half-edge (from, to), ordered by their smaller vertex, then their larger;
// kInvalidInput for an index out of range.
StatusOr<Eigen::MatrixX2i> BoundaryEdges(const TriangleMesh& mesh);

// Why `report.ok` is false, as one sentence without the file name, e.g.
// "mesh has genus 3; sdcb needs a closed genus-0 mesh". Empty when ok.
std::string DescribeTopologyProblem(const MeshTopologyReport& report);

// Ok for a mesh the spherical pipeline accepts, else kUnsupported with the
// sentence of DescribeTopologyProblem.
Status RequireClosedGenusZero(const TriangleMesh& mesh);

}  // namespace sdcb

#endif  // SDCB_CORE_MESH_MESH_TOPOLOGY_H_
