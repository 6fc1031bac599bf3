#include "sdcb/core/mesh/triangle_mesh.h"

#include <string>

namespace sdcb {

Status CheckFaceIndices(const TriangleMesh& mesh) {
  const int nv = mesh.num_vertices();
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces(f, k);
      if (v < 0 || v >= nv) {
        return InvalidInputError("face " + std::to_string(f) +
                                 " refers to vertex " + std::to_string(v) +
                                 ", but there are only " + std::to_string(nv) +
                                 " vertices");
      }
    }
  }
  return Status::Ok();
}

}  // namespace sdcb
