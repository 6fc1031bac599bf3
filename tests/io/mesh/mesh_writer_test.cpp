#include "sdcb/io/mesh/mesh_writer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "sdcb/core/common/constants.h"
#include "sdcb/io/mesh/mesh_reader.h"

namespace sdcb {
namespace {

std::string TempPath(const std::string& name) {
  return std::string(SDCB_TEST_TMP) + "/mesh_writer_" + name;
}

TriangleMesh Tetrahedron() {
  TriangleMesh m;
  m.vertices.resize(4, 3);
  // Values that need all 17 digits to round-trip.
  m.vertices << 0.1, 1.0 / 3.0, -2.0 / 7.0, 1e-300, std::sqrt(2.0), 3.0, -1.0,
      0.0, kPi, 0.5, -0.25, 1e10 / 3.0;
  m.faces.resize(4, 3);
  m.faces << 0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2;
  return m;
}

// OpenMesh's ASCII parsers behind ReadMesh read coordinates as float, so the
// reader round trip is checked to float precision; the text itself is
// parsed here with strtod to check that the doubles survive bit for bit.
void ExpectSameGeometry(const TriangleMesh& back, const TriangleMesh& mesh,
                        const std::string& what) {
  ASSERT_EQ(back.num_vertices(), mesh.num_vertices()) << what;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(back.vertices(v, k), mesh.vertices(v, k),
                  1e-7 * std::abs(mesh.vertices(v, k)) + 1e-300)
          << what << " vertex " << v;
    }
  }
  EXPECT_EQ(back.faces, mesh.faces) << what;
}

TEST(MeshWriter, RoundTripsThroughTheReader) {
  const TriangleMesh mesh = Tetrahedron();
  for (const std::string ext : {"obj", "off", "ply", "OBJ"}) {
    const std::string path = TempPath("tet." + ext);
    ASSERT_TRUE(WriteMesh(mesh, path).ok()) << ext;
    auto back = ReadMesh(path);
    ASSERT_TRUE(back.ok()) << ext << ": " << back.status().message();
    ExpectSameGeometry(*back, mesh, ext);
  }
}

TEST(MeshWriter, CoordinatesKeepEveryBit) {
  const TriangleMesh mesh = Tetrahedron();
  const std::string path = TempPath("exact.obj");
  ASSERT_TRUE(WriteMesh(mesh, path).ok());
  std::ifstream in(path);
  std::string tag;
  int v = 0;
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    fields >> tag;
    if (tag != "v") continue;
    for (int k = 0; k < 3; ++k) {
      std::string number;
      fields >> number;
      EXPECT_EQ(std::strtod(number.c_str(), nullptr), mesh.vertices(v, k))
          << number;
    }
    ++v;
  }
  EXPECT_EQ(v, 4);
}

TEST(MeshWriter, WritesPlyColors) {
  const TriangleMesh mesh = Tetrahedron();
  MeshWriteOptions options;
  options.colors.resize(4, 3);
  options.colors << 255, 0, 0, 0, 255, 0, 0, 0, 255, 12, 34, 56;
  const std::string path = TempPath("colored.ply");
  ASSERT_TRUE(WriteMesh(mesh, path, options).ok());
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("property uchar red"), std::string::npos);
  EXPECT_NE(text.str().find(" 12 34 56\n"), std::string::npos);
  auto back = ReadMesh(path);  // colors do not disturb the geometry
  ASSERT_TRUE(back.ok()) << back.status().message();
  ExpectSameGeometry(*back, mesh, "colored ply");
}

TEST(MeshWriter, RejectsBadRequestsWithoutWriting) {
  const TriangleMesh mesh = Tetrahedron();
  const std::string stl = TempPath("x.stl");
  EXPECT_EQ(WriteMesh(mesh, stl).code(), StatusCode::kInvalidArgument);
  EXPECT_FALSE(std::filesystem::exists(stl));
  MeshWriteOptions options;
  options.colors.resize(2, 3);
  options.colors.setZero();
  EXPECT_EQ(WriteMesh(mesh, TempPath("few.ply"), options).code(),
            StatusCode::kInvalidArgument);
  options.colors.resize(4, 3);
  options.colors.setZero();
  EXPECT_EQ(WriteMesh(mesh, TempPath("colors.obj"), options).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(WriteMesh(mesh, "/nonexistent-dir/x.obj").code(),
            StatusCode::kIoError);
}

}  // namespace
}  // namespace sdcb
