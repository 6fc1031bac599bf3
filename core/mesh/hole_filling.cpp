#include "sdcb/core/mesh/hole_filling.h"

#include <CGAL/Polygon_mesh_processing/border.h>

#include <algorithm>
#include <exception>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

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
