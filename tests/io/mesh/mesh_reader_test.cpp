// Tests io/mesh/mesh_reader.*: every supported format gives the same mesh, and
// hostile files give a status (never a crash, hang or silent data loss).
#include "sdcb/io/mesh/mesh_reader.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <tuple>

#include "sdcb/core/mesh/mesh_topology.h"
#include "testing/allocation_tracker.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

using testing::FreshTestDir;
using testing::MeshPath;
using testing::WriteBytes;

// `s` with control characters spelled out, for trace messages.
std::string Quoted(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '\t')
      out += "\\t";
    else if (c == '\v')
      out += "\\v";
    else if (c == '\f')
      out += "\\f";
    else if (c == '\r')
      out += "\\r";
    else if (c == '\n')
      out += "\\n";
    else if (c == '\0')
      out += "\\0";
    else
      out += c;
  }
  return "'" + out + "'";
}

// The octahedron, written by hand in each format below.
const double kOctaVertices[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                    {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
const int kOctaFaces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                              {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};

std::string OctaOff() {
  std::ostringstream s;
  s << "OFF\n# a comment\n6 8 0\n";
  for (auto& v : kOctaVertices) s << v[0] << " " << v[1] << " " << v[2] << "\n";
  for (auto& f : kOctaFaces)
    s << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
  return s.str();
}

std::string OctaObj() {
  std::ostringstream s;
  s << "# octahedron\no octa\n";
  for (auto& v : kOctaVertices)
    s << "v " << v[0] << " " << v[1] << " " << v[2] << "\n";
  s << "vn 0 0 1\n";
  for (auto& f : kOctaFaces) {
    s << "f " << f[0] + 1 << "//1 " << f[1] + 1 << "//1 " << f[2] + 1
      << "//1\n";
  }
  return s.str();
}

std::string OctaPlyAscii() {
  std::ostringstream s;
  s << "ply\nformat ascii 1.0\ncomment hi\nelement vertex 6\nproperty float x\n"
       "property float y\nproperty float z\nelement face 8\n"
       "property list uchar int vertex_indices\nend_header\n";
  for (auto& v : kOctaVertices) s << v[0] << " " << v[1] << " " << v[2] << "\n";
  for (auto& f : kOctaFaces)
    s << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
  return s.str();
}

template <typename T>
void Append(std::string* out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out->append(bytes, sizeof(T));
}

std::string OctaPlyBinary(int faces_to_write = 8) {
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 6\nproperty double "
      "x\n"
      "property double y\nproperty double z\nelement face 8\n"
      "property list uchar int vertex_indices\nend_header\n";
  for (auto& v : kOctaVertices) {
    for (double c : v) Append(&s, c);
  }
  for (int f = 0; f < faces_to_write; ++f) {
    Append<uint8_t>(&s, 3);
    for (int c : kOctaFaces[f]) Append<int32_t>(&s, c);
  }
  return s;
}

std::string OctaStlAscii() {
  std::ostringstream s;
  s << "solid octa\n";
  for (auto& f : kOctaFaces) {
    s << "  facet normal 0 0 0\n    outer loop\n";
    for (int c : f) {
      s << "      vertex " << kOctaVertices[c][0] << " " << kOctaVertices[c][1]
        << " " << kOctaVertices[c][2] << "\n";
    }
    s << "    endloop\n  endfacet\n";
  }
  s << "endsolid octa\n";
  return s.str();
}

std::string OctaStlBinary(uint32_t declared = 8, int faces_to_write = 8) {
  std::string s(80, ' ');
  Append<uint32_t>(&s, declared);
  for (int f = 0; f < faces_to_write; ++f) {
    for (int k = 0; k < 3; ++k) Append<float>(&s, 0.0f);
    for (int c : kOctaFaces[f]) {
      for (double x : kOctaVertices[c])
        Append<float>(static_cast<std::string*>(&s), static_cast<float>(x));
    }
    Append<uint16_t>(&s, 0);
  }
  return s;
}

// Triangles as sets of 3 corner positions, for comparing across formats
// that may renumber vertices (STL).
std::multiset<std::vector<double>> Triangles(const TriangleMesh& m) {
  std::multiset<std::vector<double>> out;
  for (int f = 0; f < m.num_faces(); ++f) {
    // Rotate so the smallest corner comes first, keeping orientation.
    std::vector<std::vector<double>> corners;
    for (int k = 0; k < 3; ++k) {
      const auto& p = m.vertices.row(m.faces(f, k));
      corners.push_back({p.x(), p.y(), p.z()});
    }
    const int first = static_cast<int>(
        std::min_element(corners.begin(), corners.end()) - corners.begin());
    std::vector<double> key;
    for (int k = 0; k < 3; ++k) {
      const auto& c = corners[(first + k) % 3];
      key.insert(key.end(), c.begin(), c.end());
    }
    out.insert(key);
  }
  return out;
}

TriangleMesh Octahedron() {
  TriangleMesh m;
  m.vertices.resize(6, 3);
  for (int v = 0; v < 6; ++v) {
    for (int k = 0; k < 3; ++k) m.vertices(v, k) = kOctaVertices[v][k];
  }
  m.faces.resize(8, 3);
  for (int f = 0; f < 8; ++f) {
    for (int k = 0; k < 3; ++k) m.faces(f, k) = kOctaFaces[f][k];
  }
  return m;
}

TEST(MeshReaderTest, EveryFormatGivesTheSameOctahedron) {
  const std::string dir = FreshTestDir();
  const std::map<std::string, std::string> files = {
      {"octa.off", OctaOff()},
      {"octa.obj", OctaObj()},
      {"octa_ascii.ply", OctaPlyAscii()},
      {"octa_binary.ply", OctaPlyBinary()},
      {"octa_ascii.stl", OctaStlAscii()},
      {"octa_binary.stl", OctaStlBinary()},
      {"OCTA_UPPER.OFF", OctaOff()}};
  const TriangleMesh expected = Octahedron();
  for (const auto& [name, bytes] : files) {
    SCOPED_TRACE(name);
    const std::string path = dir + "/" + name;
    WriteBytes(path, bytes);
    auto mesh = ReadMesh(path);
    ASSERT_TRUE(mesh.ok()) << mesh.status().message();
    EXPECT_EQ(mesh->num_vertices(), 6);
    EXPECT_EQ(mesh->num_faces(), 8);
    EXPECT_EQ(Triangles(*mesh), Triangles(expected));
    if (name.find(".stl") == std::string::npos) {
      // Indexed formats keep the file's vertex order and faces exactly.
      EXPECT_EQ(mesh->vertices, expected.vertices);
      EXPECT_EQ(mesh->faces, expected.faces);
    }
    EXPECT_TRUE(RequireClosedGenusZero(*mesh).ok());
  }
}

TEST(MeshReaderTest, DoublePrecisionCoordinatesSurvive) {
  // OpenMesh's readers parse float; the intake keeps the file's doubles.
  const std::string dir = FreshTestDir();
  const double x = 0.12345678901234567, y = -1234.5678901234567, z = 1e-9 / 3;
  char vertex[128];
  std::snprintf(vertex, sizeof vertex, "%.17g %.17g %.17g", x, y, z);
  std::string off =
      "OFF\n4 4 0\n" + std::string(vertex) +
      "\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  std::string obj =
      "v " + std::string(vertex) +
      "\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty double "
      "x\n"
      "property double y\nproperty double z\nelement face 4\n"
      "property list uchar int vertex_indices\nend_header\n";
  for (double c : {x, y, z, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0})
    Append(&ply, c);
  for (auto f :
       {std::array<int, 3>{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}) {
    Append<uint8_t>(&ply, 3);
    for (int i : f) Append<int32_t>(&ply, i);
  }
  for (const auto& [name, bytes] : std::map<std::string, std::string>{
           {"d.off", off}, {"d.obj", obj}, {"d.ply", ply}}) {
    SCOPED_TRACE(name);
    WriteBytes(dir + "/" + name, bytes);
    auto mesh = ReadMesh(dir + "/" + name);
    ASSERT_TRUE(mesh.ok()) << mesh.status().message();
    EXPECT_EQ(mesh->vertices(0, 0), x);
    EXPECT_EQ(mesh->vertices(0, 1), y);
    EXPECT_EQ(mesh->vertices(0, 2), z);
  }
}

TEST(MeshReaderTest, PolygonsAreTriangulatedAndVertexOrderKept) {
  const std::string dir = FreshTestDir();
  // A cube of quads, vertices in a deliberately scrambled order.
  const std::string obj =
      "v 1 1 1\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\n"
      "f 2 5 4 3\nf 6 7 1 8\nf 2 3 7 6\nf 3 4 1 7\nf 4 5 8 1\nf 5 2 6 8\n";
  WriteBytes(dir + "/cube.obj", obj);
  MeshReadInfo info;
  auto mesh = ReadMesh(dir + "/cube.obj", &info);
  ASSERT_TRUE(mesh.ok()) << mesh.status().message();
  EXPECT_EQ(info.polygons, 6);
  EXPECT_EQ(info.triangulated_polygons, 6);
  EXPECT_EQ(mesh->num_faces(), 12);
  EXPECT_EQ(mesh->vertices.row(0), Eigen::RowVector3d(1, 1, 1));
  EXPECT_EQ(mesh->vertices.row(1), Eigen::RowVector3d(0, 0, 0));
  EXPECT_EQ(mesh->vertices.row(7), Eigen::RowVector3d(0, 1, 1));
  auto report = AnalyzeMeshTopology(*mesh);
  ASSERT_TRUE(report.ok());
  EXPECT_TRUE(report->ok) << DescribeTopologyProblem(*report);
  // Fan triangulation of face 0 (2 5 4 3, 1-based): (1,4,3), (1,3,2).
  EXPECT_EQ(mesh->faces.row(0), Eigen::RowVector3i(1, 4, 3));
  EXPECT_EQ(mesh->faces.row(1), Eigen::RowVector3i(1, 3, 2));
}

// Relative indices: -1 is the last vertex defined before the face, in every
// corner form. Two tetrahedra written one after the other, each face listing
// its vertices relative to the 4 just defined; the expected faces are the
// absolute 0-based indices worked out by hand.
TEST(MeshReaderTest, ObjNegativeIndicesCountBackFromTheLastVertex) {
  const std::string obj =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
      "vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nvn 0 0 1\n"
      "f -4 -2 -3\n"                    // 0 2 1
      "f -4/-4 -3/-3 -1/-1\n"           // 0 1 3
      "f -4/-4/-1 -1/-1/-1 -2/-2/-1\n"  // 0 3 2
      "f -3//-1 -2//-1 -1//-1\n"        // 1 2 3
      "v 5 0 0\nv 6 0 0\nv 5 1 0\nv 5 0 1\n"
      "f -4 -2 -3\n"  // 4 6 5
      "f 5 6 -1\n"    // 4 5 7 (absolute and relative mixed)
      "f -4 -1 -2\n"  // 4 7 6
      "f -3 -2 8\n";  // 5 6 7
  auto mesh = ReadMeshFromBuffer(obj, MeshFileFormat::kObj);
  ASSERT_TRUE(mesh.ok()) << mesh.status().message();
  const int expected[8][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3},
                              {4, 6, 5}, {4, 5, 7}, {4, 7, 6}, {5, 6, 7}};
  ASSERT_EQ(mesh->num_faces(), 8);
  ASSERT_EQ(mesh->num_vertices(), 8);
  for (int f = 0; f < 8; ++f) {
    EXPECT_EQ(
        mesh->faces.row(f),
        Eigen::RowVector3i(expected[f][0], expected[f][1], expected[f][2]))
        << "face " << f;
  }
}

// Text starting with a byte-order mark: UTF-8's is skipped (the first
// vertex is not lost), UTF-16 is refused by name (assimp's
// box_UTF16BE.obj read as a file without faces).
TEST(MeshReaderTest, ByteOrderMarks) {
  auto mesh = ReadMeshFromBuffer(
      "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", MeshFileFormat::kObj);
  ASSERT_TRUE(mesh.ok()) << mesh.status().message();
  EXPECT_EQ(mesh->num_vertices(), 3);
  EXPECT_EQ(mesh->vertices.row(1), Eigen::RowVector3d(1, 0, 0));
  auto utf16 = ReadMeshFromBuffer(std::string("\xFE\xFF\0v\0 \0"
                                              "0",
                                              7),
                                  MeshFileFormat::kObj);
  ASSERT_FALSE(utf16.ok());
  EXPECT_EQ(utf16.status().message().rfind("the file is UTF-16 text", 0), 0u)
      << utf16.status().message();
}

// Blender 2.47 wrote a free-text line into its PLY headers (assimp's
// Wuson.ply): read with a warning naming the line; an error that follows
// names the ignored line, which may be a misspelt keyword.
TEST(MeshReaderTest, PlyFreeTextHeaderLineIsIgnoredWithAWarning) {
  const std::string ply =
      "ply\nformat ascii 1.0\n"
      "Created by Blender3D 247 - www.blender.org, source file: \n"
      "element vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\n"
      "property list uchar uint vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  MeshReadInfo info;
  auto mesh = ReadMeshFromBuffer(ply, MeshFileFormat::kPly, &info);
  ASSERT_TRUE(mesh.ok()) << mesh.status().message();
  EXPECT_EQ(mesh->num_vertices(), 3);
  EXPECT_EQ(mesh->vertices.row(1), Eigen::RowVector3d(1, 0, 0));
  EXPECT_EQ(mesh->faces.row(0), Eigen::RowVector3i(0, 1, 2));
  ASSERT_EQ(info.warnings.size(), 1u);
  EXPECT_EQ(info.warnings[0],
            "line 3 of the header ('Created by Blender3D 247 - "
            "www.blender.o...') is not a PLY keyword line; ignored");
  // A file without one has no warning.
  MeshReadInfo clean;
  ASSERT_TRUE(
      ReadMeshFromBuffer(OctaPlyAscii(), MeshFileFormat::kPly, &clean).ok());
  EXPECT_TRUE(clean.warnings.empty());
}

// CGAL's corner_poly.off: an L-shaped prism (the 2 x 2 square less a unit
// square, height 2) with two L-shaped hexagons. A fan from a hexagon's first
// corner inverts a triangle (their signed areas still add up, their unsigned
// areas do not). Closed forms: area 2 * 3 + 8 * 2 = 22, volume 6, and every
// triangle of a face has the face's outward normal.
double TriangleArea(const TriangleMesh& mesh, int f) {
  const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
  const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
  const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
  return 0.5 * (b - a).cross(c - a).norm();
}

TEST(MeshReaderTest, NonConvexPolygonsAreTriangulatedWithoutInversions) {
  auto mesh = ReadMesh(MeshPath("corner_poly.off"));
  ASSERT_TRUE(mesh.ok()) << mesh.status().message();
  ASSERT_EQ(mesh->num_faces(), 20);
  double area = 0, volume = 0;
  for (int f = 0; f < mesh->num_faces(); ++f) {
    const Eigen::Vector3d a = mesh->vertices.row(mesh->faces(f, 0));
    const Eigen::Vector3d b = mesh->vertices.row(mesh->faces(f, 1));
    const Eigen::Vector3d c = mesh->vertices.row(mesh->faces(f, 2));
    area += TriangleArea(*mesh, f);
    volume += a.dot(b.cross(c)) / 6;
  }
  EXPECT_NEAR(area, 22.0, 1e-12);
  EXPECT_NEAR(std::abs(volume), 6.0, 1e-12);

  // The same holds for an OBJ whose faces come before their vertices (the
  // polygon is clipped once the vertices are known): an L-shaped hexagon
  // and its fan-free reverse close a flat double-sided L of area 2 * 3.
  const std::string obj =
      "f 1 2 3 4 5 6\nf 6 5 4 3 2 1\n"
      "v 0 1 0\nv 1 1 0\nv 1 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\n";
  auto flat = ReadMeshFromBuffer(obj, MeshFileFormat::kObj);
  ASSERT_TRUE(flat.ok()) << flat.status().message();
  double flat_area = 0;
  for (int f = 0; f < flat->num_faces(); ++f) {
    flat_area += TriangleArea(*flat, f);
  }
  EXPECT_NEAR(flat_area, 6.0, 1e-12);
}

// Reads the counts on the OFF header line of a CGAL data file.
std::pair<int, int> OffHeaderCounts(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line.find("OFF") != std::string::npos)
      continue;
    std::istringstream s(line);
    int v = -1, f = -1;
    s >> v >> f;
    if (v >= 0) return {v, f};
  }
  return {-1, -1};
}

TEST(MeshReaderTest, CgalMeshesMatchTheirHeaders) {
  for (const char* name : {"bunny00.off", "fandisk.off", "cow.off",
                           "blobby.off", "sphere966.off", "cube-meshed.off"}) {
    SCOPED_TRACE(name);
    const auto [nv, nf] = OffHeaderCounts(MeshPath(name));
    ASSERT_GT(nv, 0) << "run scripts/setup.sh to extract CGAL's meshes";
    auto mesh = ReadMesh(MeshPath(name));
    ASSERT_TRUE(mesh.ok()) << mesh.status().message();
    EXPECT_EQ(mesh->num_vertices(), nv);
    EXPECT_EQ(mesh->num_faces(), nf);  // all of these are triangle meshes
  }
}

// Reads `bytes` as a file called `name`; expects failure whose message starts
// with the path and contains `needle`.
void ExpectRefused(const std::string& name, const std::string& bytes,
                   const std::string& needle) {
  SCOPED_TRACE(name);
  const std::string path = FreshTestDir() + "/" + name;
  WriteBytes(path, bytes);
  auto mesh = ReadMesh(path);
  ASSERT_FALSE(mesh.ok()) << "accepted a bad file";
  const std::string& message = mesh.status().message();
  EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
  EXPECT_NE(message.find(needle), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << "one line only";
}

TEST(MeshReaderTest, MissingEmptyAndDirectory) {
  const std::string dir = FreshTestDir();
  auto missing = ReadMesh(dir + "/nothing.off");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.status().message().find("no such file"), std::string::npos);
  auto directory = ReadMesh(dir);
  ASSERT_FALSE(directory.ok());
  EXPECT_NE(directory.status().message().find("directory"), std::string::npos);
  ExpectRefused("empty.obj", "", "empty");
  ExpectRefused("mesh.xyz", "1 2 3\n", "unknown mesh format");
}

TEST(MeshReaderTest, HostileOffFiles) {
  ExpectRefused("huge.off", "OFF\n2000000000 2000000000 0\n0 0 0\n",
                "2000000000");
  ExpectRefused("negative.off", "OFF\n-5 -3 0\n", "negative");
  ExpectRefused("header_only.off", "OFF\n", "counts");
  ExpectRefused("counts_only.off", "OFF\n4 4 0\n", "cannot fit");
  ExpectRefused("many_corners.off",
                "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n999999999 0 1 2\n" +
                    std::string(64, ' '),
                "999999999 corners");
  std::string truncated = OctaOff();
  truncated.resize(truncated.size() - 20);
  ExpectRefused("truncated.off", truncated, "truncated");
  ExpectRefused("bad_index.off",
                "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 9\n"
                "3 0 2 3\n3 1 2 3\n",
                "refers to vertex 9");
  ExpectRefused("nan.off",
                "OFF\n4 4 0\n0 0 0\n1 nan 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n"
                "3 0 2 3\n3 1 2 3\n",
                "not a finite number");
  ExpectRefused("text.off",
                "OFF\n4 4 0\n0 0 0\n1 abc 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n"
                "3 0 2 3\n3 1 2 3\n",
                "'abc'");
}

TEST(MeshReaderTest, HostileObjFiles) {
  const std::string tet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
  ExpectRefused("out_of_range.obj", tet + "f 1 2 3\nf 1 2 5\n",
                "refers to vertex 5");
  ExpectRefused("zero_index.obj", tet + "f 0 1 2\n", "refers to vertex 0");
  ExpectRefused("before_first.obj", tet + "f -1 -2 -5\n",
                "refers to vertex -5, but only 4 vertices are defined");
  ExpectRefused("before_defined.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n",
                "only 2 vertices are defined");
  ExpectRefused("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n",
                "not a finite number");
  ExpectRefused("inf.obj", "v 0 0 0\nv 1 inf 0\nv 0 1 0\nf 1 2 3\n",
                "not a finite number");
  ExpectRefused("text.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n",
                "'zero'");
  ExpectRefused("short_vertex.obj", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
                "fewer than three");
  ExpectRefused("two_corners.obj", tet + "f 1 2\n", "2 corners");
  ExpectRefused("no_faces.obj", tet, "no faces");
}

TEST(MeshReaderTest, HostilePlyFiles) {
  std::string truncated = OctaPlyBinary(/*faces_to_write=*/5);
  ExpectRefused("truncated_binary.ply", truncated, "truncated");
  std::string cut = OctaPlyBinary();
  cut.resize(cut.size() - 3);
  ExpectRefused("cut_binary.ply", cut, "truncated");
  ExpectRefused(
      "huge.ply",
      "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
      "property float x\nproperty float y\nproperty float z\nend_header\n",
      "4000000000");
  ExpectRefused("no_end.ply", "ply\nformat ascii 1.0\nelement vertex 3\n",
                "end_header");
  std::string bad_index = OctaPlyAscii();
  bad_index.replace(bad_index.rfind("3 0 3 5"), 7, "3 0 3 6");
  ExpectRefused("bad_index.ply", bad_index, "refers to vertex 6");
  std::string nan = OctaPlyAscii();
  nan.replace(nan.find("end_header\n1 0 0") + 11, 1, "nan");
  ExpectRefused("nan.ply", nan, "non-finite");
}

TEST(MeshReaderTest, HostileStlFiles) {
  ExpectRefused("truncated_binary.stl", OctaStlBinary(8, 5), "truncated");
  ExpectRefused("short.stl", std::string(40, '\x01'), "too short");
  std::string cut = OctaStlAscii();
  cut.resize(cut.size() / 2);
  ExpectRefused("truncated_ascii.stl", cut, "truncated");
}

TEST(MeshReaderTest, RandomBytesNeverCrash) {
  std::mt19937 rng(7);
  for (const char* ext : {".off", ".obj", ".ply", ".stl"}) {
    for (int trial = 0; trial < 5; ++trial) {
      std::string bytes(64 + 97 * trial, '\0');
      for (char& c : bytes) c = static_cast<char>(rng());
      const std::string path =
          FreshTestDir() + "/random" + std::to_string(trial) + ext;
      WriteBytes(path, bytes);
      auto mesh = ReadMesh(path);
      EXPECT_FALSE(mesh.ok()) << path;
    }
  }
}

TEST(MeshReaderTest, TruncationsOfValidFilesNeverCrash) {
  // Every prefix of a valid binary PLY / STL and ascii OFF: refused or, for
  // the full file, accepted; never a crash.
  const std::string dir = FreshTestDir();
  const std::map<std::string, std::string> files = {{"p.ply", OctaPlyBinary()},
                                                    {"s.stl", OctaStlBinary()},
                                                    {"o.off", OctaOff()}};
  for (const auto& [name, bytes] : files) {
    for (size_t n = 0; n < bytes.size(); n += 7) {
      const std::string path = dir + "/" + std::to_string(n) + name;
      WriteBytes(path, bytes.substr(0, n));
      auto mesh = ReadMesh(path);
      if (mesh.ok()) {
        // Only a prefix that still holds the whole mesh may be accepted.
        EXPECT_EQ(mesh->num_faces(), 8) << path;
      }
    }
  }
}

// ---------------------------------------------------------------------------
// One parser per format, reading from memory.

StatusOr<TriangleMesh> FromBuffer(const std::string& bytes,
                                  MeshFileFormat format,
                                  const MeshReadLimits& limits = {}) {
  return ReadMeshFromBuffer(bytes, format, nullptr, limits);
}

TEST(MeshReaderTest, BufferAndPathGiveTheSameMesh) {
  const std::string dir = FreshTestDir();
  const std::vector<std::tuple<std::string, std::string, MeshFileFormat>>
      files = {{"o.off", OctaOff(), MeshFileFormat::kOff},
               {"o.obj", OctaObj(), MeshFileFormat::kObj},
               {"o.ply", OctaPlyBinary(), MeshFileFormat::kPly},
               {"o.stl", OctaStlAscii(), MeshFileFormat::kStl}};
  for (const auto& [name, bytes, format] : files) {
    SCOPED_TRACE(name);
    WriteBytes(dir + "/" + name, bytes);
    auto from_path = ReadMesh(dir + "/" + name);
    auto from_buffer = FromBuffer(bytes, format);
    ASSERT_TRUE(from_path.ok() && from_buffer.ok());
    EXPECT_EQ(from_path->vertices, from_buffer->vertices);
    EXPECT_EQ(from_path->faces, from_buffer->faces);
    EXPECT_EQ(MeshFileFormatFromPath(dir + "/" + name).value(), format);
  }
  EXPECT_FALSE(MeshFileFormatFromPath("x.3ds").ok());
  // Errors from memory carry no file name; from a path they start with it.
  auto bad = FromBuffer("OFF\n-1 0 0\n", MeshFileFormat::kOff);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().message().rfind("the header", 0), 0u)
      << bad.status().message();
}

// The octahedron of kOctaVertices written with the given separator between
// tokens, line end, and comment lines in every place a comment may go.
std::string OctaOffWith(const std::string& sep, const std::string& eol) {
  std::ostringstream s;
  s << "# before the header" << eol << "OFF" << sep << "# after the keyword"
    << eol << eol << "6" << sep << "8" << sep << "0" << eol
    << "# between the sections" << eol;
  for (auto& v : kOctaVertices) {
    s << v[0] << sep << v[1] << sep << v[2] << sep << "# trailing" << eol;
  }
  s << eol << "  # indented comment" << eol;
  for (auto& f : kOctaFaces) {
    s << "3" << sep << f[0] << sep << f[1] << sep << f[2] << eol;
  }
  return s.str();
}

void ExpectOctahedron(const StatusOr<TriangleMesh>& mesh) {
  ASSERT_TRUE(mesh.ok()) << mesh.status().message();
  const TriangleMesh expected = Octahedron();
  EXPECT_EQ(mesh->vertices, expected.vertices);
  EXPECT_EQ(mesh->faces, expected.faces);
}

TEST(MeshReaderTest, CommentsWhitespaceAndLineEndsAnywhere) {
  for (const std::string sep : {" ", "\t", " \t\v ", "\f"}) {
    for (const std::string eol : {"\n", "\r\n"}) {
      SCOPED_TRACE("separator " + Quoted(sep) + " eol " + Quoted(eol));
      ExpectOctahedron(FromBuffer(OctaOffWith(sep, eol), MeshFileFormat::kOff));
      std::string obj = OctaObj();
      std::string converted;
      for (char c : obj) {
        if (c == '\n') {
          converted += " # comment" + eol;
        } else if (c == ' ') {
          converted += sep;
        } else {
          converted += c;
        }
      }
      ExpectOctahedron(FromBuffer(converted, MeshFileFormat::kObj));
      std::string ply = OctaPlyAscii(), ply_converted;
      for (char c : ply) ply_converted += c == '\n' ? eol : std::string(1, c);
      ExpectOctahedron(FromBuffer(ply_converted, MeshFileFormat::kPly));
    }
  }
  // The counts on the keyword's line, and face colors after the corners
  // (OpenMesh misread both).
  std::string off = "OFF 6 8 0\n";
  for (auto& v : kOctaVertices) {
    off += std::to_string(v[0]) + " " + std::to_string(v[1]) + " " +
           std::to_string(v[2]) + "\n";
  }
  for (auto& f : kOctaFaces) {
    off += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " +
           std::to_string(f[2]) + " .7 0 0\n";
  }
  ExpectOctahedron(FromBuffer(off, MeshFileFormat::kOff));
}

TEST(MeshReaderTest, UnusualNumbersReadExactly) {
  // Finite doubles beyond float range, hex floats, denormals, signs, and
  // values below the smallest double (read as zero); strtod in the C locale
  // is the oracle.
  const std::vector<std::string> numbers = {"1e300",
                                            "-2.5e-300",
                                            "0x1.8p1",
                                            "-0X1P-3",
                                            "4.9e-324",
                                            "+7",
                                            "1e-400",
                                            ".5",
                                            "5.",
                                            "-0",
                                            "3.4028236e38",
                                            "1e39",
                                            "0x1.fffffffffffffp1023",
                                            "0012.50"};
  for (const std::string& x : numbers) {
    SCOPED_TRACE(x);
    const double expected = std::strtod(x.c_str(), nullptr);
    const std::string off = "OFF\n4 4 0\n" + x +
                            " 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                            "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    const std::string obj = "v " + x +
                            " 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                            "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\n"
        "property double y\nproperty double z\nelement face 4\n"
        "property list uchar int vertex_indices\nend_header\n" +
        x + " 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    for (const auto& [bytes, format] : {std::pair{off, MeshFileFormat::kOff},
                                        std::pair{obj, MeshFileFormat::kObj},
                                        std::pair{ply, MeshFileFormat::kPly}}) {
      auto mesh = FromBuffer(bytes, format);
      ASSERT_TRUE(mesh.ok()) << mesh.status().message();
      EXPECT_EQ(std::memcmp(&mesh->vertices(0, 0), &expected, 8), 0)
          << mesh->vertices(0, 0) << " vs " << expected;
    }
  }
  for (const std::string& bad : std::vector<std::string>{
           "1e400", "-1e999", "inf", "-nan", "0x", "1e", "+-1", "1.5.5", "1,5",
           "0x1p99999", std::string("1\0.5", 4)}) {
    SCOPED_TRACE(Quoted(bad));
    const std::string off = "OFF\n4 4 0\n" + bad +
                            " 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                            "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    auto mesh = FromBuffer(off, MeshFileFormat::kOff);
    ASSERT_FALSE(mesh.ok());
    EXPECT_NE(mesh.status().message().find("not a finite number"),
              std::string::npos)
        << mesh.status().message();
    EXPECT_EQ(mesh.status().message().find('\0'), std::string::npos);
  }
}

// Bytes of `value` in big-endian order.
template <typename T>
void AppendBigEndian(std::string* out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  for (size_t i = sizeof(T); i-- > 0;) out->push_back(bytes[i]);
}

TEST(MeshReaderTest, PlyVariants) {
  // Big endian, int16 coordinates, extra vertex properties (a NaN normal),
  // a vertex_index list with uint counts, an extra element before the faces.
  std::string ply =
      "ply\r\nformat binary_big_endian 1.0\r\ncomment c\r\nobj_info o\r\n"
      "element vertex 6\r\nproperty float nx\r\nproperty short x\r\n"
      "property short y\r\nproperty short z\r\n"
      "property list uchar float tex\r\n"
      "element edge 1\r\nproperty int a\r\nproperty int b\r\n"
      "element face 8\r\nproperty uint vertex_index\r\n"
      "property list uint int vertex_index\r\nend_header\r\n";
  for (auto& v : kOctaVertices) {
    AppendBigEndian<float>(&ply, std::nanf(""));
    for (double c : v) AppendBigEndian<int16_t>(&ply, static_cast<int16_t>(c));
    AppendBigEndian<uint8_t>(&ply, 2);
    AppendBigEndian<float>(&ply, 0.5f);
    AppendBigEndian<float>(&ply, 0.25f);
  }
  AppendBigEndian<int32_t>(&ply, 0);
  AppendBigEndian<int32_t>(&ply, 1);
  for (auto& f : kOctaFaces) {
    AppendBigEndian<uint32_t>(&ply, 77);  // a scalar of the same name first
    AppendBigEndian<uint32_t>(&ply, 3);
    for (int c : f) AppendBigEndian<int32_t>(&ply, c);
  }
  // The scalar "vertex_index" comes first; the list of that name is the
  // corner list.
  ExpectOctahedron(FromBuffer(ply, MeshFileFormat::kPly));

  // Faces before vertices: indices are checked against the declared count.
  std::string faces_first =
      "ply\nformat ascii 1.0\nelement face 8\n"
      "property list uchar int vertex_indices\nelement vertex 6\n"
      "property double x\nproperty double y\nproperty double z\n"
      "end_header\n";
  for (auto& f : kOctaFaces) {
    faces_first += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) +
                   " " + std::to_string(f[2]) + "\n";
  }
  for (auto& v : kOctaVertices) {
    faces_first += std::to_string(v[0]) + " " + std::to_string(v[1]) + " " +
                   std::to_string(v[2]) + "\n";
  }
  ExpectOctahedron(FromBuffer(faces_first, MeshFileFormat::kPly));
}

TEST(MeshReaderTest, StlVariants) {
  // A binary STL whose header starts with "solid" is binary by its size.
  std::string binary = OctaStlBinary();
  binary.replace(0, 11, "solid octa ");
  auto b = FromBuffer(binary, MeshFileFormat::kStl);
  ASSERT_TRUE(b.ok()) << b.status().message();
  EXPECT_EQ(Triangles(*b), Triangles(Octahedron()));
  EXPECT_EQ(b->num_vertices(), 6);
  // Two solids, NaN normals, -0 equal to 0 (merged into one vertex), CRLF.
  std::string ascii = OctaStlAscii();
  ascii.replace(ascii.find("normal 0 0 0"), 12, "normal nan nan nan");
  ascii.replace(ascii.find("vertex 0 1 0"), 12, "vertex -0 1 -0");
  const size_t half = ascii.find("  facet", ascii.size() / 2);
  ascii.insert(half, "endsolid octa\nsolid second\n");
  std::string crlf;
  for (char c : ascii)
    crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  auto a = FromBuffer(crlf, MeshFileFormat::kStl);
  ASSERT_TRUE(a.ok()) << a.status().message();
  EXPECT_EQ(a->num_vertices(), 6);
  EXPECT_EQ(a->num_faces(), 8);
  EXPECT_TRUE(RequireClosedGenusZero(*a).ok());
}

TEST(MeshReaderTest, ObjNeverOpensNamedFilesAndAcceptsForwardIndices) {
  // mtllib naming a FIFO: opening it for reading would block forever.
  const std::string dir = FreshTestDir();
  const std::string fifo = dir + "/materials.mtl";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string obj = "mtllib " + fifo +
                          "\nmtllib /dev/zero\nusemtl red\n"
                          "f 1/1/1 3/2/1 2/3/1\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
                          "v 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0\nv 0 0 1\n";
  WriteBytes(dir + "/tet.obj", obj);
  auto mesh = ReadMesh(dir + "/tet.obj");
  ASSERT_TRUE(mesh.ok()) << mesh.status().message();
  EXPECT_EQ(mesh->num_vertices(), 4);
  EXPECT_EQ(mesh->faces.row(0), Eigen::RowVector3i(0, 2, 1));
  EXPECT_TRUE(RequireClosedGenusZero(*mesh).ok());
  // A device or FIFO named as the mesh itself is refused, never read.
  auto device = ReadMesh(fifo.substr(0, fifo.size() - 4) + ".obj");
  EXPECT_FALSE(device.ok());
  ASSERT_EQ(::symlink("/dev/zero", (dir + "/zero.off").c_str()), 0);
  auto zero = ReadMesh(dir + "/zero.off");
  ASSERT_FALSE(zero.ok());
  EXPECT_NE(zero.status().message().find("not a regular file"),
            std::string::npos)
      << zero.status().message();
}

TEST(MeshReaderTest, HeaderShapesOpenMeshMisread) {
  // Classes of files that crashed, hung or exploded in memory with the
  // pre-scan + OpenMesh reader: each is now one clear error.
  const std::string ply_head = "ply\nformat ascii 1.0\n";
  ExpectRefused(
      "property_first.ply",
      ply_head + "property float x\nelement vertex 1\nend_header\n1\n",
      "property before any element");
  ExpectRefused("format_no_version.ply",
                "ply\nformat ascii\nelement vertex 1\nproperty float x\n"
                "end_header\n1\n",
                "format");
  ExpectRefused("element_short.ply",
                ply_head + "element vertex\nproperty float x\nend_header\n",
                "element NAME COUNT");
  ExpectRefused("huge_declared.ply",
                ply_head +
                    "element vertex 200000000\nproperty float x\n"
                    "property float y\nproperty float z\nend_header\n0 0 0\n",
                "do not fit");
  ExpectRefused("unknown_keyword.ply",
                ply_head + "elemnt vertex 3\nend_header\n",
                "no vertex element (line 3 of the header ('elemnt vertex 3') "
                "is not a PLY keyword line, and was ignored)");
  ExpectRefused("empty_element.ply",
                ply_head + "element vertex 1000000000\nend_header\n",
                "no properties");
  ExpectRefused(
      "nul_in_number.off",
      std::string("OFF\n3 1 0\n0 0 0\n1 0\0.5 0\n0 1 0\n3 0 1 2\n", 34),
      "not a finite number");
  ExpectRefused("tab_counts.off",
                "OFF\t3\v1\t0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n",
                "refers to vertex 9");
  ExpectRefused("binary.off", "OFF BINARY\n" + std::string(100, '\0'),
                "binary OFF");
  ExpectRefused("four_d.off", "4OFF\n1 1 0\n0 0 0 0\n", "higher-dimensional");
  ExpectRefused(
      "huge_polygon.obj",
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nf" +
          [] {
            std::string s;
            for (int i = 0; i < 100'001; ++i) s += " 1";
            return s;
          }() +
          "\n",
      "more than 100000 corners");
  ExpectRefused("solid_garbage.stl", "solid x\nfacet normal 0 0 0\nbogus\n",
                "expected 'outer loop'");
}

TEST(MeshReaderTest, LimitsAreEnforcedWithClearMessages) {
  const std::string off = OctaOff();
  MeshReadLimits limits;
  limits.max_vertices = 5;
  auto v = FromBuffer(off, MeshFileFormat::kOff, limits);
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.status().code(), StatusCode::kUnsupported);
  EXPECT_NE(v.status().message().find("more than 5 vertices"),
            std::string::npos)
      << v.status().message();
  limits = {};
  limits.max_triangles = 7;
  for (const auto& [bytes, format] :
       {std::pair{off, MeshFileFormat::kOff},
        std::pair{OctaObj(), MeshFileFormat::kObj},
        std::pair{OctaStlBinary(), MeshFileFormat::kStl}}) {
    auto t = FromBuffer(bytes, format, limits);
    ASSERT_FALSE(t.ok());
    EXPECT_NE(t.status().message().find("more than 7 triangles"),
              std::string::npos)
        << t.status().message();
  }
  limits = {};
  // The octahedron: its ~110 bytes plus 2 x (6 x 24 + 8 x 12) = 480.
  limits.max_memory_bytes = 500;
  auto m = FromBuffer(off, MeshFileFormat::kOff, limits);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.status().message().find("memory"), std::string::npos);
  limits.max_memory_bytes = 700;
  EXPECT_TRUE(FromBuffer(off, MeshFileFormat::kOff, limits).ok());
  limits = {};
  limits.max_polygon_corners = 3;
  auto p = ReadMeshFromBuffer("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n",
                              MeshFileFormat::kObj, nullptr, limits);
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.status().message().find("more than 3 corners"), std::string::npos)
      << p.status().message();
  limits = {};
  limits.max_file_bytes = 100;
  const std::string path = FreshTestDir() + "/big.off";
  WriteBytes(path, off);
  auto f = ReadMesh(path, nullptr, limits);
  ASSERT_FALSE(f.ok());
  EXPECT_NE(f.status().message().find("limit"), std::string::npos);
}

TEST(MeshReaderTest, DeclaredCountsNeverAllocateBeyondTheFile) {
  // Counts that the old reader allocated for (4.6 GB for a 2e8-vertex PLY)
  // are refused without any allocation much larger than the file.
  const std::vector<std::pair<std::string, MeshFileFormat>> files = {
      {"ply\nformat binary_little_endian 1.0\nelement vertex 200000000\n"
       "property double x\nproperty double y\nproperty double z\n"
       "element face 1\nproperty list uchar int vertex_indices\n"
       "end_header\n" +
           std::string(4096, '\0'),
       MeshFileFormat::kPly},
      {"OFF\n199999999 1 0\n" + std::string(4096, ' '), MeshFileFormat::kOff},
      {"OFF\n500 500 0\n" + std::string(8000, ' '), MeshFileFormat::kOff},
      {std::string(80, ' ') + std::string("\xff\xff\xff\x0f", 4) +
           std::string(4096, '\0'),
       MeshFileFormat::kStl}};
  for (const auto& [bytes, format] : files) {
    SCOPED_TRACE(bytes.substr(0, 40));
    const size_t largest = testing::LargestAllocationDuring(
        [&] { EXPECT_FALSE(FromBuffer(bytes, format).ok()); });
    EXPECT_LT(largest, 16 * bytes.size() + 4096);
  }
  // The tracker sees the reader: a valid file of 600 vertices allocates
  // their 600 x 3 doubles.
  std::string valid = "OFF\n600 200 0\n";
  for (int v = 0; v < 600; ++v) valid += "0 0 " + std::to_string(v) + "\n";
  for (int f = 0; f < 200; ++f) {
    valid += "3 " + std::to_string(3 * f) + " " + std::to_string(3 * f + 1) +
             " " + std::to_string(3 * f + 2) + "\n";
  }
  const size_t largest = testing::LargestAllocationDuring(
      [&] { EXPECT_TRUE(FromBuffer(valid, MeshFileFormat::kOff).ok()); });
  EXPECT_GE(largest, 600u * 3 * sizeof(double));
}

}  // namespace
}  // namespace sdcb
