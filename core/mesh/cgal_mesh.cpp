// CGAL's fair() solves with Eigen only when CGAL_EIGEN3_ENABLED is defined;
// it is defined here alone, not for the whole library, so that no other
// CGAL call of the library changes the code path it takes.
#ifndef CGAL_EIGEN3_ENABLED
#define CGAL_EIGEN3_ENABLED
#endif

#include "sdcb/core/mesh/cgal_mesh.h"

#include <CGAL/Polygon_mesh_processing/fair.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/refine.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <array>
#include <iterator>
#include <utility>
#include <vector>

#include "sdcb/core/mesh/mesh_topology.h"

namespace sdcb {

bool ToCgalMesh(const TriangleMesh& mesh, CgalMesh* out) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  out->clear();
  std::vector<CgalKernel::Point_3> points;
  points.reserve(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    points.emplace_back(mesh.vertices(v, 0), mesh.vertices(v, 1),
                        mesh.vertices(v, 2));
  }
  std::vector<std::array<int, 3>> triangles(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    triangles[f] = {mesh.faces(f, 0), mesh.faces(f, 1), mesh.faces(f, 2)};
  }
  // What PMP::is_polygon_soup_a_polygon_mesh tests, in linear time (CGAL's
  // test spent more than the conversion itself on large meshes).
  for (const std::array<int, 3>& t : triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) return false;
  }
  const StatusOr<MeshTopologyReport> topology = AnalyzeMeshTopology(mesh);
  if (!topology.ok() || topology->non_manifold_edges > 0 ||
      topology->non_manifold_vertices > 0 ||
      topology->inconsistently_oriented_edges > 0) {
    return false;
  }
  // Vertex i of the soup becomes vertex i of the mesh (isolated vertices
  // included), so indices survive.
  PMP::polygon_soup_to_polygon_mesh(points, triangles, *out);
  return true;
}

TriangleMesh FromCgalMesh(const CgalMesh& mesh) {
  TriangleMesh out;
  out.vertices.resize(mesh.number_of_vertices(), 3);
  std::vector<int> index(mesh.num_vertices(), -1);
  int next = 0;
  for (CgalMesh::Vertex_index v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    out.vertices.row(next) << p.x(), p.y(), p.z();
    index[v] = next++;
  }
  out.faces.resize(mesh.number_of_faces(), 3);
  int row = 0;
  for (CgalMesh::Face_index f : mesh.faces()) {
    int k = 0;
    for (CgalMesh::Vertex_index v :
         CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (k < 3) out.faces(row, k) = index[v];
      ++k;
    }
    ++row;
  }
  return out;
}

namespace {

// Closes the hole of `border` with a fan around a new vertex at its
// vertices' centroid; the new faces are appended to `faces`. False (mesh
// unchanged) if Surface_mesh refuses a face.
bool FanFill(CgalMesh::Halfedge_index border, CgalMesh* mesh,
             std::vector<CgalMesh::Face_index>* faces) {
  std::vector<std::pair<CgalMesh::Vertex_index, CgalMesh::Vertex_index>> sides;
  double x = 0, y = 0, z = 0;
  for (CgalMesh::Halfedge_index h :
       CGAL::halfedges_around_face(border, *mesh)) {
    sides.emplace_back(mesh->source(h), mesh->target(h));
    const CgalKernel::Point_3& p = mesh->point(mesh->target(h));
    x += p.x();
    y += p.y();
    z += p.z();
  }
  const double n = static_cast<double>(sides.size());
  const CgalMesh::Vertex_index c =
      mesh->add_vertex(CgalKernel::Point_3(x / n, y / n, z / n));
  std::vector<CgalMesh::Face_index> added;
  for (const auto& [s, t] : sides) {
    // The border half-edge s -> t becomes an edge of the new face.
    const CgalMesh::Face_index f = mesh->add_face(s, t, c);
    if (f == CgalMesh::null_face()) {
      for (CgalMesh::Face_index g : added)
        CGAL::Euler::remove_face(mesh->halfedge(g), *mesh);
      mesh->remove_vertex(c);
      return false;
    }
    added.push_back(f);
  }
  faces->insert(faces->end(), added.begin(), added.end());
  return true;
}

}  // namespace

std::optional<HoleFillMethod> FillCgalHole(CgalMesh::Halfedge_index border,
                                           const CgalHoleFillOptions& options,
                                           CgalMesh* mesh, int* added_faces,
                                           int* added_vertices) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  const auto faces_before = mesh->number_of_faces();
  const auto vertices_before = mesh->number_of_vertices();
  int edges = 0;
  for (CgalMesh::Halfedge_index h :
       CGAL::halfedges_around_face(border, *mesh)) {
    (void)h;
    ++edges;
  }
  std::vector<CgalMesh::Face_index> patch;
  if (options.cgal_triangulation) {
    PMP::triangulate_hole(
        *mesh, border, std::back_inserter(patch),
        CGAL::parameters::use_2d_constrained_delaunay_triangulation(
            options.use_2d_delaunay)
            .use_delaunay_triangulation(true)
            .do_not_use_cubic_algorithm(edges >
                                        options.max_cubic_search_edges));
  }
  HoleFillMethod method = HoleFillMethod::kTriangulated;
  if (patch.empty()) {
    if (!options.fan_fallback || !FanFill(border, mesh, &patch)) {
      return std::nullopt;
    }
    method = HoleFillMethod::kFan;
  }
  if (options.refine) {
    std::vector<CgalMesh::Face_index> new_faces;
    std::vector<CgalMesh::Vertex_index> new_vertices;
    PMP::refine(*mesh, patch, std::back_inserter(new_faces),
                std::back_inserter(new_vertices));
    const int n = static_cast<int>(new_vertices.size());
    // A patch refine split nothing stays "triangulated" (nothing to fair).
    if (method == HoleFillMethod::kTriangulated && n > 0) {
      method = HoleFillMethod::kRefined;
    }
    if (n > 0 && n <= options.max_fair_vertices &&
        PMP::fair(*mesh, new_vertices) && method == HoleFillMethod::kRefined) {
      method = HoleFillMethod::kFaired;
    }
  }
  if (added_faces != nullptr) {
    *added_faces = static_cast<int>(mesh->number_of_faces() - faces_before);
  }
  if (added_vertices != nullptr) {
    *added_vertices =
        static_cast<int>(mesh->number_of_vertices() - vertices_before);
  }
  return method;
}

}  // namespace sdcb
