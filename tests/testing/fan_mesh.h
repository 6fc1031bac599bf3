// Small meshes for tests and benchmarks: a CAD-style fan, a double cone, two
// fans of n triangles around the poles (0, 0, +-1) over a ring of n vertices
// on the equator (the shape of a tessellated cylinder cap; hub valence n);
// and the regular tetrahedron.
#ifndef SDCB_TESTS_TESTING_FAN_MESH_H_
#define SDCB_TESTS_TESTING_FAN_MESH_H_

#include <cmath>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb::testing {

// Corners (+-1, +-1, +-1) with an even number of minus signs, faces
// counter-clockwise seen from outside; edge 2 sqrt 2.
inline TriangleMesh RegularTetrahedron() {
  TriangleMesh m;
  m.vertices.resize(4, 3);
  m.vertices << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  m.faces.resize(4, 3);
  m.faces << 0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2;
  return m;
}

// n + 2 vertices (the poles first), 2n faces, closed, genus 0, oriented
// outward.
inline TriangleMesh DoubleCone(int n) {
  TriangleMesh m;
  m.vertices.resize(n + 2, 3);
  m.vertices.row(0) << 0, 0, 1;
  m.vertices.row(1) << 0, 0, -1;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * kPi * i / n;
    m.vertices.row(2 + i) << std::cos(a), std::sin(a), 0;
  }
  m.faces.resize(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.faces.row(2 * i) << 0, 2 + i, 2 + j;
    m.faces.row(2 * i + 1) << 1, 2 + j, 2 + i;
  }
  return m;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_FAN_MESH_H_
