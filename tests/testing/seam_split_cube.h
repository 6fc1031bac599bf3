// The unit cube as OBJ / PLY writers with per-face normals or UVs store it:
// each of its six quads with its own four vertices (24), so no two faces
// share a vertex. For the seam weld's tests (core/mesh/vertex_welding.h).
#ifndef SDCB_TESTS_TESTING_SEAM_SPLIT_CUBE_H_
#define SDCB_TESTS_TESTING_SEAM_SPLIT_CUBE_H_

#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb::testing {

// The unit cube's corners and its six faces as outward (counter-clockwise
// seen from outside) quads of corner numbers.
inline constexpr double kCubeCorners[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},
                                              {0, 1, 0}, {0, 0, 1}, {1, 0, 1},
                                              {1, 1, 1}, {0, 1, 1}};
inline constexpr int kCubeQuads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7},
                                         {0, 1, 5, 4}, {1, 2, 6, 5},
                                         {2, 3, 7, 6}, {3, 0, 4, 7}};

// Quad q's vertices are rows 4q..4q+3 (its corners in order), its
// triangles rows 2q (corners 0 1 2) and 2q+1 (0 2 3); `lift` raises the
// top quad (q = 1) off the sides by that much.
inline TriangleMesh SeamSplitCube(double lift = 0) {
  TriangleMesh mesh;
  mesh.vertices.resize(24, 3);
  mesh.faces.resize(12, 3);
  for (int q = 0; q < 6; ++q) {
    for (int k = 0; k < 4; ++k) {
      const double* c = kCubeCorners[kCubeQuads[q][k]];
      mesh.vertices.row(4 * q + k) << c[0], c[1], c[2] + (q == 1 ? lift : 0);
    }
    mesh.faces.row(2 * q) << 4 * q, 4 * q + 1, 4 * q + 2;
    mesh.faces.row(2 * q + 1) << 4 * q, 4 * q + 2, 4 * q + 3;
  }
  return mesh;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_SEAM_SPLIT_CUBE_H_
