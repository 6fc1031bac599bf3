// A minimal OFF reader for core tests, which may not link io/ (the layer
// above core). Reads CGAL's data meshes: '#' comments, "OFF" header,
// triangles only. Fails the calling test on anything else.
#ifndef SDCB_TESTS_CORE_OFF_TEST_MESH_H_
#define SDCB_TESTS_CORE_OFF_TEST_MESH_H_

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "core/triangle_mesh.h"

namespace sdcb::testing {

inline TriangleMesh LoadOffTestMesh(const std::string& name) {
  std::ifstream in(std::string(SDCB_MESH_DIR) + "/" + name);
  EXPECT_TRUE(in.good()) << name;
  std::stringstream text;
  std::string line;
  while (std::getline(in, line)) {
    const size_t hash = line.find('#');
    text << line.substr(0, hash) << "\n";
  }
  std::string header;
  int nv = 0, nf = 0, ne = 0;
  text >> header >> nv >> nf >> ne;
  EXPECT_EQ(header, "OFF") << name;
  TriangleMesh m;
  m.vertices.resize(nv, 3);
  m.faces.resize(nf, 3);
  for (int v = 0; v < nv; ++v)
    text >> m.vertices(v, 0) >> m.vertices(v, 1) >> m.vertices(v, 2);
  for (int f = 0; f < nf; ++f) {
    int corners = 0;
    text >> corners >> m.faces(f, 0) >> m.faces(f, 1) >> m.faces(f, 2);
    EXPECT_EQ(corners, 3) << name << " face " << f;
  }
  EXPECT_FALSE(text.fail()) << name;
  return m;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_CORE_OFF_TEST_MESH_H_
