// One of CGAL's sample meshes (data/meshes) read through io's reader, for
// tests and checks that link io. Fails the calling test if it does not read.
#ifndef SDCB_TESTS_TESTING_CGAL_TEST_MESH_H_
#define SDCB_TESTS_TESTING_CGAL_TEST_MESH_H_

#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "sdcb/io/mesh/mesh_reader.h"
#include "testing/temp_dir.h"

namespace sdcb::testing {

inline TriangleMesh ReadCgalMesh(const std::string& name) {
  auto mesh = ReadMesh(MeshPath(name));
  EXPECT_TRUE(mesh.ok()) << mesh.status().message();
  return mesh.ok() ? std::move(mesh).value() : TriangleMesh();
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_CGAL_TEST_MESH_H_
