// A TriangleMesh from lists of vertices and faces, for tests that write
// small meshes out by hand, and the cube several tests fit.
#ifndef SDCB_TESTS_TESTING_MAKE_MESH_H_
#define SDCB_TESTS_TESTING_MAKE_MESH_H_

#include <Eigen/Core>
#include <vector>

#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb::testing {

inline TriangleMesh MakeMesh(const std::vector<Eigen::Vector3d>& vertices,
                             const std::vector<Eigen::Vector3i>& faces) {
  TriangleMesh mesh;
  mesh.vertices.resize(vertices.size(), 3);
  for (size_t i = 0; i < vertices.size(); ++i) {
    mesh.vertices.row(i) = vertices[i].transpose();
  }
  mesh.faces.resize(faces.size(), 3);
  for (size_t f = 0; f < faces.size(); ++f) {
    mesh.faces.row(f) = faces[f].transpose();
  }
  return mesh;
}

// CGAL's data/meshes/cube.off: [-1, 1]^3 in 12 triangles.
inline TriangleMesh CubeMesh() {
  return MakeMesh({{-1, -1, -1},
                   {-1, 1, -1},
                   {1, 1, -1},
                   {1, -1, -1},
                   {-1, -1, 1},
                   {-1, 1, 1},
                   {1, 1, 1},
                   {1, -1, 1}},
                  {{0, 1, 3},
                   {3, 1, 2},
                   {0, 4, 1},
                   {1, 4, 5},
                   {3, 2, 7},
                   {7, 2, 6},
                   {4, 0, 3},
                   {7, 4, 3},
                   {6, 4, 7},
                   {6, 5, 4},
                   {1, 5, 6},
                   {2, 1, 6}});
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_MAKE_MESH_H_
