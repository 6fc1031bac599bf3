#include "sdcb/core/mesh/hole_filling.h"

#include <CGAL/Polygon_mesh_processing/border.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <queue>
#include <string>
#include <utility>
#include <vector>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/common/union_find.h"
#include "sdcb/core/mesh/cgal_mesh.h"
#include "sdcb/core/mesh/mesh_topology.h"

namespace sdcb {
namespace {

// CGAL's search over all triangulations of a loop of n edges takes O(n^3)
// time and O(n^2) memory: tried only for loops this short when the
// Delaunay-based searches find nothing.
constexpr int kMaxCubicSearchEdges = 300;
// Fairing solves a sparse system in the refined patch's new vertices;
// larger patches keep the refined triangulation.
constexpr int kMaxFairVertices = 20000;

// A boundary loop of the part and one of its CGAL border half-edges.
struct Loop {
  std::vector<int> vertices;  // in the header's direction, smallest first
  CgalMesh::Halfedge_index border;
};

// The part's boundary loops, in the order of their smallest vertex row.
std::vector<Loop> BoundaryLoops(const CgalMesh& mesh) {
  std::vector<CgalMesh::Halfedge_index> cycles;
  CGAL::Polygon_mesh_processing::extract_boundary_cycles(
      mesh, std::back_inserter(cycles));
  std::vector<Loop> loops;
  for (CgalMesh::Halfedge_index border : cycles) {
    Loop loop;
    loop.border = border;
    // Border half-edges have no face; the part's face beside the border
    // half-edge s -> t runs t -> s, so the loop is the cycle reversed.
    for (CgalMesh::Halfedge_index h :
         CGAL::halfedges_around_face(border, mesh)) {
      loop.vertices.push_back(static_cast<int>(mesh.target(h)));
    }
    std::reverse(loop.vertices.begin(), loop.vertices.end());
    std::rotate(loop.vertices.begin(),
                std::min_element(loop.vertices.begin(), loop.vertices.end()),
                loop.vertices.end());
    loops.push_back(std::move(loop));
  }
  std::sort(loops.begin(), loops.end(), [](const Loop& a, const Loop& b) {
    return a.vertices.front() < b.vertices.front();
  });
  return loops;
}

// Whether face f of `mesh` has the corners of `corners` in the same cyclic
// order.
bool SameFace(const CgalMesh& mesh, CgalMesh::Face_index f,
              const Eigen::Vector3i& corners) {
  std::vector<int> v;
  for (CgalMesh::Vertex_index x :
       CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
    v.push_back(static_cast<int>(x));
  }
  if (v.size() != 3) return false;
  for (int r = 0; r < 3; ++r) {
    if (v[r] == corners[0] && v[(r + 1) % 3] == corners[1] &&
        v[(r + 2) % 3] == corners[2]) {
      return true;
    }
  }
  return false;
}

// A fill that folds back over the part: its faces beside the boundary face
// away from the part's (a flat part's planar hole, filled in its own plane,
// lies on the part with the opposite orientation, and no smooth surface
// follows a closed mesh through such a fold). Each such fill is lifted
// into a dome off the part's side: its vertices move along the fill's area
// vector (outward of the closed mesh) by kDomeHeight times the radius of a
// disk of the fill's area, times sin(pi/2 s), s the vertex's distance from
// the loop over the fill's edges relative to the farthest. The fill then
// leaves the boundary at an angle instead of doubling back.
constexpr double kFoldBackCosine = -0.3;  // mean over the loop's edges
constexpr double kDomeHeight = 0.5;

// Unit normals of the faces of `mesh`.
Eigen::MatrixX3d FaceNormals(const TriangleMesh& mesh) {
  Eigen::MatrixX3d n(mesh.num_faces(), 3);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    const Eigen::Vector3d x = (b - a).cross(c - a);
    n.row(f) = (x.norm() > 0 ? x.normalized() : x).transpose();
  }
  return n;
}

void LiftFoldedFills(FilledMesh* filled) {
  TriangleMesh& mesh = filled->mesh;
  const int nf = mesh.num_faces(), nv = mesh.num_vertices();
  const int first_fill = filled->input_faces;
  if (first_fill == nf) return;
  const Eigen::MatrixX3d normal = FaceNormals(mesh);
  // Per undirected edge, its faces; fills as components of fill faces.
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.faces(f, k), b = mesh.faces(f, (k + 1) % 3);
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  }
  UnionFind fills(nf);
  std::vector<double> cos_sum(nf, 0.0);
  std::vector<int> cos_count(nf, 0);
  std::vector<std::pair<int, int>> boundary_faces;  // (fill face, part face)
  for (const auto& [edge, faces] : edge_faces) {
    if (faces.size() != 2) continue;
    const bool fill0 = faces[0] >= first_fill, fill1 = faces[1] >= first_fill;
    if (fill0 && fill1) fills.Union(faces[0], faces[1]);
    if (fill0 != fill1) {
      boundary_faces.emplace_back(fill0 ? faces[0] : faces[1],
                                  fill0 ? faces[1] : faces[0]);
    }
  }
  for (const auto& [fill, part] : boundary_faces) {
    const int root = fills.Find(fill);
    cos_sum[root] += normal.row(fill).dot(normal.row(part));
    ++cos_count[root];
  }
  // Distance from the part over the fill's edges (Dijkstra), per vertex.
  std::vector<double> distance(nv, std::numeric_limits<double>::infinity());
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (int v = 0; v < filled->input_vertices; ++v) {
    distance[v] = 0;
    queue.push({0.0, v});
  }
  std::vector<std::vector<int>> neighbours(nv);
  for (const auto& [edge, faces] : edge_faces) {
    neighbours[edge.first].push_back(edge.second);
    neighbours[edge.second].push_back(edge.first);
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v]) continue;
    for (const int w : neighbours[v]) {
      const double dw =
          d + (mesh.vertices.row(v) - mesh.vertices.row(w)).norm();
      if (dw < distance[w]) {
        distance[w] = dw;
        queue.push({dw, w});
      }
    }
  }
  // Each folded fill's area vector, area, farthest distance and vertices.
  std::map<int, Eigen::Vector3d> area_vector;
  std::map<int, double> area, farthest;
  std::map<int, std::vector<int>> vertices;
  for (int f = first_fill; f < nf; ++f) {
    const int root = fills.Find(f);
    if (cos_count[root] == 0 ||
        cos_sum[root] / cos_count[root] > kFoldBackCosine) {
      continue;
    }
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    const Eigen::Vector3d x = 0.5 * (b - a).cross(c - a);
    auto [it, added] = area_vector.emplace(root, Eigen::Vector3d::Zero());
    it->second += x;
    area[root] += x.norm();
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces(f, k);
      if (v < filled->input_vertices) continue;
      vertices[root].push_back(v);
      farthest[root] = std::max(farthest[root], distance[v]);
    }
  }
  for (auto& [root, list] : vertices) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    const Eigen::Vector3d direction = area_vector[root].normalized();
    const double height = kDomeHeight * std::sqrt(area[root] / kPi);
    if (!(farthest[root] > 0) || !direction.allFinite()) continue;
    for (const int v : list) {
      const double s = std::min(1.0, distance[v] / farthest[root]);
      mesh.vertices.row(v) +=
          (height * std::sin(0.5 * kPi * s) * direction).transpose();
    }
  }
}

StatusOr<FilledMesh> Fill(const TriangleMesh& part) {
  FilledMesh out;
  out.mesh = part;
  out.input_vertices = part.num_vertices();
  out.input_faces = part.num_faces();
  CgalMesh mesh;
  if (!ToCgalMesh(part, &mesh)) {
    return InvalidInputError(
        "cannot fill the part's holes: it is not a consistently oriented "
        "2-manifold");
  }
  std::vector<Loop> loops = BoundaryLoops(mesh);
  CgalHoleFillOptions options;
  options.use_2d_delaunay = true;
  options.max_cubic_search_edges = kMaxCubicSearchEdges;
  options.fan_fallback = true;
  options.refine = true;
  options.max_fair_vertices = kMaxFairVertices;
  // A lone triangle's hole is the triangle itself: triangulated, it would
  // give two triangles back to back on three vertices, which no sphere map
  // embeds. A fan from its centroid makes a tetrahedron's combinatorics
  // (then lifted into a dome, LiftFoldedFills).
  options.cgal_triangulation = part.num_faces() > 1;
  for (Loop& loop : loops) {
    const std::optional<HoleFillMethod> method =
        FillCgalHole(loop.border, options, &mesh, nullptr, nullptr);
    if (!method) {
      return InvalidInputError(
          "cannot fill the hole of " + std::to_string(loop.vertices.size()) +
          " edges at vertex " + std::to_string(loop.vertices.front()));
    }
    out.boundary_loops.push_back(std::move(loop.vertices));
    out.fill_methods.push_back(*method);
  }
  if (loops.empty()) return out;
  // The part's rows stay as they are; the fill's elements follow in CGAL's
  // index order (they were appended; none of the part's was removed).
  std::vector<int> row(mesh.num_vertices(), -1);
  int next = out.input_vertices;
  std::vector<Eigen::Vector3d> added_vertices;
  for (CgalMesh::Vertex_index v : mesh.vertices()) {
    if (static_cast<int>(v) < out.input_vertices) {
      row[v] = static_cast<int>(v);
      continue;
    }
    const CgalKernel::Point_3& p = mesh.point(v);
    added_vertices.emplace_back(p.x(), p.y(), p.z());
    row[v] = next++;
  }
  std::vector<Eigen::Vector3i> added_faces;
  for (CgalMesh::Face_index f : mesh.faces()) {
    if (static_cast<int>(f) < out.input_faces) {
      if (!SameFace(mesh, f, part.faces.row(f).transpose())) {
        return InvalidInputError(
            "cannot fill the part's holes: the filling changed face " +
            std::to_string(static_cast<int>(f)) + " of the part");
      }
      continue;
    }
    Eigen::Vector3i corners;
    int k = 0;
    for (CgalMesh::Vertex_index x :
         CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (k < 3) corners[k] = row[x];
      ++k;
    }
    added_faces.push_back(corners);
  }
  out.mesh.vertices.conservativeResize(next, 3);
  for (size_t i = 0; i < added_vertices.size(); ++i) {
    out.mesh.vertices.row(out.input_vertices + static_cast<int>(i)) =
        added_vertices[i].transpose();
  }
  out.mesh.faces.conservativeResize(
      out.input_faces + static_cast<int>(added_faces.size()), 3);
  for (size_t i = 0; i < added_faces.size(); ++i) {
    out.mesh.faces.row(out.input_faces + static_cast<int>(i)) =
        added_faces[i].transpose();
  }
  LiftFoldedFills(&out);
  SDCB_ASSIGN_OR_RETURN(const MeshTopologyReport topology,
                        AnalyzeMeshTopology(out.mesh));
  if (!topology.ok) {
    return InvalidInputError("after filling its holes, " +
                             DescribeTopologyProblem(topology));
  }
  return out;
}

}  // namespace

const char* HoleFillMethodName(HoleFillMethod method) {
  switch (method) {
    case HoleFillMethod::kFaired:
      return "faired";
    case HoleFillMethod::kRefined:
      return "refined";
    case HoleFillMethod::kTriangulated:
      return "triangulated";
    case HoleFillMethod::kFan:
      return "fan";
  }
  return "?";
}

TriangleMesh FilledMesh::Part() const {
  TriangleMesh part;
  part.vertices = mesh.vertices.topRows(input_vertices);
  part.faces = mesh.faces.topRows(input_faces);
  return part;
}

StatusOr<FilledMesh> FillHoles(const TriangleMesh& part) {
  SDCB_RETURN_IF_ERROR(CheckFaceIndices(part));
  try {
    return Fill(part);
  } catch (const std::exception& e) {
    // CGAL reports violated preconditions by exceptions, over several lines.
    std::string what = e.what();
    std::replace(what.begin(), what.end(), '\n', ' ');
    return InvalidInputError("cannot fill the part's holes (" + what + ")");
  }
}

}  // namespace sdcb
