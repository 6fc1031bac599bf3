// Tests io/mesh_reader.*: every supported format gives the same mesh, and
// hostile files give a status (never a crash, hang or silent data loss).
#include "sdcb/io/mesh_reader.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

#include "sdcb/core/mesh/mesh_topology.h"
#include "testing/temp_dir.h"

namespace sdcb {
namespace {

using testing::FreshTestDir;
using testing::MeshPath;
using testing::WriteBytes;

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
  ExpectRefused("negative.obj", tet + "f -1 -2 -3\n", "negative");
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

}  // namespace
}  // namespace sdcb
