#include "sdcb/core/mesh/mesh_topology.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <vector>

#include "sdcb/core/common/union_find.h"
#include "sdcb/core/mesh/vertex_welding.h"

namespace sdcb {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

// One directed edge of a triangle: from -> to, in face `face`, whose corner
// at `from` is corner index 3 * face + k.
struct HalfEdge {
  int lo, hi;  // the undirected key, lo < hi
  int from, to;
  int face;
  int from_corner;
};

// Faces with a repeated index or three exactly collinear points.
int CountDegenerateFaces(const TriangleMesh& mesh) {
  int count = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const int a = mesh.faces(f, 0), b = mesh.faces(f, 1), c = mesh.faces(f, 2);
    bool degenerate = (a == b || b == c || a == c);
    if (!degenerate) {
      auto point = [&](int v) {
        return Kernel::Point_3(mesh.vertices(v, 0), mesh.vertices(v, 1),
                               mesh.vertices(v, 2));
      };
      degenerate = CGAL::collinear(point(a), point(b), point(c));
    }
    if (degenerate) ++count;
  }
  return count;
}

// Vertices at the coordinates of an earlier one.
int CountDuplicateVertices(const TriangleMesh& mesh) {
  const std::vector<int> number = EqualPositionNumbers(mesh.vertices);
  return number.empty() ? 0
                        : mesh.num_vertices() - 1 -
                              *std::max_element(number.begin(), number.end());
}

// The half-edges of the non-degenerate face edges, grouped by undirected
// edge (a strict total order: the parallel sort's result is then unique).
std::vector<HalfEdge> SortedHalfEdges(const TriangleMesh& mesh) {
  const int nf = mesh.num_faces();
  std::vector<HalfEdge> half_edges;
  half_edges.reserve(3 * static_cast<size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int from = mesh.faces(f, k), to = mesh.faces(f, (k + 1) % 3);
      if (from == to) continue;
      half_edges.push_back(
          {std::min(from, to), std::max(from, to), from, to, f, 3 * f + k});
    }
  }
  tbb::parallel_sort(half_edges.begin(), half_edges.end(),
                     [](const HalfEdge& a, const HalfEdge& b) {
                       if (a.lo != b.lo) return a.lo < b.lo;
                       if (a.hi != b.hi) return a.hi < b.hi;
                       if (a.face != b.face) return a.face < b.face;
                       return a.from_corner < b.from_corner;
                     });
  return half_edges;
}

}  // namespace

StatusOr<Eigen::MatrixX2i> BoundaryEdges(const TriangleMesh& mesh) {
  SDCB_RETURN_IF_ERROR(CheckFaceIndices(mesh));
  const std::vector<HalfEdge> half_edges = SortedHalfEdges(mesh);
  std::vector<const HalfEdge*> single;
  for (size_t i = 0; i < half_edges.size();) {
    size_t j = i + 1;
    while (j < half_edges.size() && half_edges[j].lo == half_edges[i].lo &&
           half_edges[j].hi == half_edges[i].hi) {
      ++j;
    }
    if (j - i == 1) single.push_back(&half_edges[i]);
    i = j;
  }
  Eigen::MatrixX2i edges(static_cast<Eigen::Index>(single.size()), 2);
  for (size_t e = 0; e < single.size(); ++e) {
    edges.row(static_cast<Eigen::Index>(e)) << single[e]->from, single[e]->to;
  }
  return edges;
}

StatusOr<MeshTopologyReport> AnalyzeMeshTopology(const TriangleMesh& mesh) {
  SDCB_RETURN_IF_ERROR(CheckFaceIndices(mesh));
  const int nv = mesh.num_vertices();
  const int nf = mesh.num_faces();

  MeshTopologyReport r;
  r.vertices = nv;
  r.faces = nf;

  r.degenerate_faces = CountDegenerateFaces(mesh);
  r.duplicate_vertices = CountDuplicateVertices(mesh);
  const std::vector<HalfEdge> half_edges = SortedHalfEdges(mesh);

  UnionFind vertex_sets(nv);
  for (int f = 0; f < nf; ++f) {
    vertex_sets.Union(mesh.faces(f, 0), mesh.faces(f, 1));
    vertex_sets.Union(mesh.faces(f, 0), mesh.faces(f, 2));
  }
  // Corners around a vertex that share an edge are joined; a manifold vertex
  // ends with all its corners in one set (one fan).
  UnionFind corner_sets(3 * nf);
  auto corner_of = [&](int face, int vertex) {
    for (int k = 0; k < 3; ++k) {
      if (mesh.faces(face, k) == vertex) return 3 * face + k;
    }
    return -1;
  };
  UnionFind boundary_sets(nv);
  std::vector<char> on_boundary(nv, 0);
  std::vector<int> edges_per_root(nv, 0);

  for (size_t i = 0; i < half_edges.size();) {
    size_t j = i;
    while (j < half_edges.size() && half_edges[j].lo == half_edges[i].lo &&
           half_edges[j].hi == half_edges[i].hi) {
      ++j;
    }
    const int count = static_cast<int>(j - i);
    const HalfEdge& e = half_edges[i];
    ++r.edges;
    ++edges_per_root[vertex_sets.Find(e.lo)];
    if (count == 1) {
      ++r.boundary_edges;
      boundary_sets.Union(e.lo, e.hi);
      on_boundary[e.lo] = on_boundary[e.hi] = 1;
    } else if (count >= 3) {
      ++r.non_manifold_edges;
    } else if (half_edges[i].from == half_edges[i + 1].from) {
      ++r.inconsistently_oriented_edges;
    }
    for (size_t m = i + 1; m < j; ++m) {
      for (int endpoint : {e.lo, e.hi}) {
        corner_sets.Union(corner_of(half_edges[i].face, endpoint),
                          corner_of(half_edges[m].face, endpoint));
      }
    }
    i = j;
  }

  // Fans per vertex, faces and boundary loops per component.
  std::vector<int> first_fan(nv, -1);
  std::vector<char> referenced(nv, 0), several_fans(nv, 0);
  for (int c = 0; c < 3 * nf; ++c) {
    const int v = mesh.faces(c / 3, c % 3);
    const int fan = corner_sets.Find(c);
    referenced[v] = 1;
    if (first_fan[v] < 0) {
      first_fan[v] = fan;
    } else if (first_fan[v] != fan) {
      several_fans[v] = 1;
    }
  }
  std::vector<int> vertices_per_root(nv, 0), faces_per_root(nv, 0),
      loops_per_root(nv, 0);
  std::vector<char> is_root(nv, 0);
  for (int f = 0; f < nf; ++f)
    ++faces_per_root[vertex_sets.Find(mesh.faces(f, 0))];
  for (int v = 0; v < nv; ++v) {
    if (!referenced[v]) {
      ++r.unreferenced_vertices;
      continue;
    }
    if (several_fans[v]) ++r.non_manifold_vertices;
    const int root = vertex_sets.Find(v);
    ++vertices_per_root[root];
    if (!is_root[root]) {
      is_root[root] = 1;
      ++r.components;
    }
    if (on_boundary[v] && boundary_sets.Find(v) == v) {
      ++r.boundary_loops;
      ++loops_per_root[root];
    }
  }
  int genus_twice = 0;
  for (int v = 0; v < nv; ++v) {
    if (!is_root[v]) continue;
    const int chi =
        vertices_per_root[v] - edges_per_root[v] + faces_per_root[v];
    r.euler_characteristic += chi;
    genus_twice += 2 - chi - loops_per_root[v];
  }
  r.genus = genus_twice / 2;
  r.ok = nf > 0 && r.boundary_edges == 0 && r.non_manifold_edges == 0 &&
         r.non_manifold_vertices == 0 && r.inconsistently_oriented_edges == 0 &&
         r.components == 1 && r.genus == 0 && r.degenerate_faces == 0 &&
         r.unreferenced_vertices == 0;
  return r;
}

std::string DescribeTopologyProblem(const MeshTopologyReport& r) {
  const std::string need = "; sdcb needs a closed genus-0 triangle mesh";
  auto n = [](int x) { return std::to_string(x); };
  if (r.ok) return "";
  if (r.faces == 0) return "mesh has no faces" + need;
  if (r.non_manifold_edges > 0) {
    return "mesh has " + n(r.non_manifold_edges) +
           " non-manifold edges (three or more triangles on one edge)" + need;
  }
  if (r.boundary_edges > 0) {
    return "mesh is an open surface with " + n(r.boundary_edges) +
           " boundary edges in " + n(r.boundary_loops) +
           (r.boundary_loops == 1 ? " boundary loop" : " boundary loops") +
           need;
  }
  if (r.non_manifold_vertices > 0) {
    return "mesh has " + n(r.non_manifold_vertices) +
           " non-manifold vertices (several surface sheets meet there)" + need;
  }
  if (r.components != 1) {
    return "mesh has " + n(r.components) + " connected components" + need;
  }
  if (r.inconsistently_oriented_edges > 0) {
    return "mesh is not consistently oriented (" +
           n(r.inconsistently_oriented_edges) +
           " edges are used twice in the same direction)" + need;
  }
  if (r.genus != 0) return "mesh has genus " + n(r.genus) + need;
  if (r.degenerate_faces > 0) {
    return "mesh has " + n(r.degenerate_faces) +
           " degenerate (zero-area) triangles" + need;
  }
  if (r.unreferenced_vertices > 0) {
    return "mesh has " + n(r.unreferenced_vertices) +
           " vertices that no triangle uses" + need;
  }
  return "mesh is not a closed genus-0 triangle mesh";
}

Status RequireClosedGenusZero(const TriangleMesh& mesh) {
  SDCB_ASSIGN_OR_RETURN(const MeshTopologyReport report,
                        AnalyzeMeshTopology(mesh));
  if (report.ok) return Status::Ok();
  return UnsupportedError(DescribeTopologyProblem(report));
}

}  // namespace sdcb
