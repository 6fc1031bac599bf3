#include "sdcb/core/mesh/cgal_mesh.h"

#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>

#include <array>
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

}  // namespace sdcb
