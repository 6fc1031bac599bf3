// A TriangleMesh from lists of vertices and faces, for tests that write
// small meshes out by hand.
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

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_MAKE_MESH_H_
