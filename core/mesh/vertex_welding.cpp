#include "sdcb/core/mesh/vertex_welding.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <numeric>

#include "sdcb/core/mesh/mesh_topology.h"

namespace sdcb {

std::vector<int> EqualPositionNumbers(const Eigen::MatrixX3d& vertices) {
  const int nv = static_cast<int>(vertices.rows());
  auto key = [&](int v) {
    return std::array<double, 3>{vertices(v, 0), vertices(v, 1),
                                 vertices(v, 2)};
  };
  // Sorted by position, then by index: each run of equal positions starts
  // with its first vertex (a strict total order: the result is unique).
  std::vector<int> order(nv);
  std::iota(order.begin(), order.end(), 0);
  tbb::parallel_sort(order.begin(), order.end(), [&](int a, int b) {
    const std::array<double, 3> ka = key(a), kb = key(b);
    return ka != kb ? ka < kb : a < b;
  });
  std::vector<int> first(nv);
  for (int i = 0; i < nv; ++i) {
    first[order[i]] = i > 0 && key(order[i]) == key(order[i - 1])
                          ? first[order[i - 1]]
                          : order[i];
  }
  std::vector<int> number(nv);
  int distinct = 0;
  for (int v = 0; v < nv; ++v) {
    number[v] = first[v] == v ? distinct++ : number[first[v]];
  }
  return number;
}

WeldedMesh WeldEqualPositions(const TriangleMesh& mesh) {
  WeldedMesh welded;
  welded.new_vertex = EqualPositionNumbers(mesh.vertices);
  const int nv = mesh.num_vertices();
  const int distinct = nv == 0
                           ? 0
                           : 1 + *std::max_element(welded.new_vertex.begin(),
                                                   welded.new_vertex.end());
  if (distinct == nv) {
    welded.mesh = mesh;
    return welded;
  }
  welded.mesh.vertices.resize(distinct, 3);
  for (int v = 0; v < nv; ++v) {
    welded.mesh.vertices.row(welded.new_vertex[v]) = mesh.vertices.row(v);
  }
  welded.mesh.faces.resize(mesh.num_faces(), 3);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      welded.mesh.faces(f, k) = welded.new_vertex[mesh.faces(f, k)];
    }
  }
  return welded;
}

std::string SeamWeldReport::Describe() const {
  if (merged_vertices == 0) return "";
  return "merged " + std::to_string(merged_vertices) +
         (merged_vertices == 1 ? " vertex" : " vertices") +
         " split at equal positions (UV or normal seams)";
}

namespace {

std::string Count(int n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// Why welding (`before` -> `after`) would make the mesh worse; empty if it
// would not.
std::string WeldHarm(const MeshTopologyReport& before,
                     const MeshTopologyReport& after) {
  const int edges = after.non_manifold_edges - before.non_manifold_edges;
  const int vertices =
      after.non_manifold_vertices - before.non_manifold_vertices;
  const int oriented = after.inconsistently_oriented_edges -
                       before.inconsistently_oriented_edges;
  if (edges > 0) {
    return "merging them would make " + Count(edges, "edge", "edges") +
           " non-manifold";
  }
  if (vertices > 0) {
    return "merging them would make " + Count(vertices, "vertex", "vertices") +
           " non-manifold";
  }
  if (oriented > 0) {
    return "merging them would join " + Count(oriented, "edge", "edges") +
           " between triangles of opposite orientations";
  }
  return "";
}

}  // namespace

StatusOr<WeldedMesh> WeldSeams(const TriangleMesh& mesh,
                               SeamWeldReport* report) {
  *report = SeamWeldReport();
  SDCB_RETURN_IF_ERROR(CheckFaceIndices(mesh));
  WeldedMesh welded = WeldEqualPositions(mesh);
  const int merged = welded.merged_vertices();
  if (merged == 0) return welded;
  SDCB_ASSIGN_OR_RETURN(const MeshTopologyReport before,
                        AnalyzeMeshTopology(mesh));
  SDCB_ASSIGN_OR_RETURN(const MeshTopologyReport after,
                        AnalyzeMeshTopology(welded.mesh));
  // A weld that closes no boundary edge (of a closed mesh's stray copies,
  // or of copies no triangle uses) gains nothing: neither done nor
  // reported.
  const bool closes = after.boundary_edges < before.boundary_edges;
  const std::string harm = closes ? WeldHarm(before, after) : "";
  if (closes && harm.empty()) {
    report->merged_vertices = merged;
    return welded;
  }
  if (closes) {
    report->declined_vertices = merged;
    report->declined_because = harm;
  }
  WeldedMesh unchanged;
  unchanged.mesh = mesh;
  unchanged.new_vertex.resize(mesh.num_vertices());
  std::iota(unchanged.new_vertex.begin(), unchanged.new_vertex.end(), 0);
  return unchanged;
}

}  // namespace sdcb
