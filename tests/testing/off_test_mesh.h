// A minimal OFF reader for core tests, which may not link io/ (the layer
// above core). Reads CGAL's data meshes: '#' comments, OFF/COFF header,
// one vertex or face per line, triangles only. Fails the calling test on
// anything else.
#ifndef SDCB_TESTS_TESTING_OFF_TEST_MESH_H_
#define SDCB_TESTS_TESTING_OFF_TEST_MESH_H_

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb::testing {

inline TriangleMesh LoadOffTestMesh(const std::string& name) {
  std::ifstream in(std::string(SDCB_MESH_DIR) + "/" + name);
  EXPECT_TRUE(in.good()) << name;
  // Non-empty lines without comments; vertex lines may carry colors (COFF)
  // and face lines colors after the indices: only the leading numbers count.
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    line = line.substr(0, line.find('#'));
    if (line.find_first_not_of(" \t\r") != std::string::npos)
      lines.push_back(line);
  }
  TriangleMesh m;
  if (lines.size() < 2) {
    ADD_FAILURE() << name << ": no OFF header";
    return m;
  }
  EXPECT_NE(lines[0].find("OFF"), std::string::npos) << name;
  int nv = 0, nf = 0;
  std::istringstream(lines[1]) >> nv >> nf;
  EXPECT_EQ(static_cast<int>(lines.size()), 2 + nv + nf) << name;
  if (static_cast<int>(lines.size()) < 2 + nv + nf) return m;
  m.vertices.resize(nv, 3);
  m.faces.resize(nf, 3);
  for (int v = 0; v < nv; ++v) {
    std::istringstream(lines[2 + v]) >> m.vertices(v, 0) >> m.vertices(v, 1) >>
        m.vertices(v, 2);
  }
  for (int f = 0; f < nf; ++f) {
    int corners = 0;
    std::istringstream(lines[2 + nv + f]) >> corners >> m.faces(f, 0) >>
        m.faces(f, 1) >> m.faces(f, 2);
    EXPECT_EQ(corners, 3) << name << " face " << f;
  }
  return m;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_OFF_TEST_MESH_H_
