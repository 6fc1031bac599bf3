// Makes the scale benchmark's inputs from a real mesh: bunny00 (37,706
// vertices) refined by OpenMesh's uniform subdividers, written as binary
// little-endian PLY (float coordinates, as scanners write them):
//   bunny_113k.ply  sqrt(3) x1             113,114 vertices
//   bunny_339k.ply  sqrt(3) x2             339,338
//   bunny_1m.ply    sqrt(3) x3           1,018,010   (the "~1M" input)
//   bunny_4m.ply    Loop x1, sqrt(3) x3  4,072,034   (the "~4M" input)
// sqrt(3) subdivision (Kobbelt 2000) triples the faces per step, Loop
// quadruples them; both are approximating, so the surfaces are smooth
// refinements of the scan, not copies with duplicated vertices.
//   scale_meshes [INPUT.off] OUT_DIR
// With --split N, the input split N times, every triangle into four at its
// edges' midpoints, written to OUT.ply: the same surface (its thin parts and
// sharp edges stay as they are) with 4^N times the faces, e.g. CGAL's
// armadillo at N = 3 (1,664,002 vertices, docs/SCALE.md):
//   scale_meshes --split N INPUT OUT.ply
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/Sqrt3T.hh>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unordered_map>

#include "sdcb/io/mesh/mesh_reader.h"

namespace {

using OmMesh = OpenMesh::TriMesh_ArrayKernelT<>;

OmMesh ToOpenMesh(const sdcb::TriangleMesh& m) {
  OmMesh om;
  std::vector<OmMesh::VertexHandle> v(m.num_vertices());
  for (int i = 0; i < m.num_vertices(); ++i) {
    v[i] = om.add_vertex(
        OmMesh::Point(m.vertices(i, 0), m.vertices(i, 1), m.vertices(i, 2)));
  }
  for (int f = 0; f < m.num_faces(); ++f) {
    om.add_face(v[m.faces(f, 0)], v[m.faces(f, 1)], v[m.faces(f, 2)]);
  }
  return om;
}

// Writes `om` to `path`; on failure removes what was written.
bool WriteBinaryPly(const OmMesh& om, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  out << "ply\nformat binary_little_endian 1.0\nelement vertex "
      << om.n_vertices()
      << "\nproperty float x\nproperty float y\nproperty float z\n"
         "element face "
      << om.n_faces()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& vh : om.vertices()) {
    const OmMesh::Point& p = om.point(vh);
    const float xyz[3] = {static_cast<float>(p[0]), static_cast<float>(p[1]),
                          static_cast<float>(p[2])};
    out.write(reinterpret_cast<const char*>(xyz), sizeof(xyz));
  }
  for (const auto& fh : om.faces()) {
    const unsigned char n = 3;
    out.write(reinterpret_cast<const char*>(&n), 1);
    for (const auto& vh : om.fv_range(fh)) {
      const int index = vh.idx();
      out.write(reinterpret_cast<const char*>(&index), sizeof(index));
    }
  }
  out.close();
  if (out) return true;
  std::error_code error;  // no partial file (a device stays)
  if (std::filesystem::is_regular_file(path, error)) {
    std::filesystem::remove(path, error);
  }
  return false;
}

// Every triangle into four at its edges' midpoints: the input's vertices
// first, then one per edge in the order the faces first meet it.
sdcb::TriangleMesh SplitAtMidpoints(const sdcb::TriangleMesh& m) {
  std::vector<Eigen::RowVector3d> vertices;
  for (int i = 0; i < m.num_vertices(); ++i) {
    vertices.push_back(m.vertices.row(i));
  }
  std::unordered_map<int64_t, int> midpoint;
  const auto mid = [&](int a, int b) {
    const int64_t key =
        static_cast<int64_t>(std::min(a, b)) * m.num_vertices() +
        std::max(a, b);
    const auto [it, inserted] =
        midpoint.emplace(key, static_cast<int>(vertices.size()));
    if (inserted) {
      vertices.push_back(0.5 * (m.vertices.row(a) + m.vertices.row(b)));
    }
    return it->second;
  };
  sdcb::TriangleMesh out;
  out.faces.resize(4 * m.num_faces(), 3);
  for (int f = 0; f < m.num_faces(); ++f) {
    const int a = m.faces(f, 0), b = m.faces(f, 1), c = m.faces(f, 2);
    const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
    out.faces.row(4 * f) << a, ab, ca;
    out.faces.row(4 * f + 1) << ab, b, bc;
    out.faces.row(4 * f + 2) << ca, bc, c;
    out.faces.row(4 * f + 3) << ab, bc, ca;
  }
  out.vertices.resize(static_cast<Eigen::Index>(vertices.size()), 3);
  for (size_t i = 0; i < vertices.size(); ++i) {
    out.vertices.row(static_cast<Eigen::Index>(i)) = vertices[i];
  }
  return out;
}

int SplitMain(int times, const std::string& input, const std::string& output) {
  auto mesh = sdcb::ReadMesh(input);
  if (!mesh.ok()) {
    std::fprintf(stderr, "%s\n", mesh.status().message().c_str());
    return 1;
  }
  sdcb::TriangleMesh m = std::move(mesh).value();
  for (int i = 0; i < times; ++i) m = SplitAtMidpoints(m);
  const OmMesh om = ToOpenMesh(m);
  if (!WriteBinaryPly(om, output)) {
    std::fprintf(stderr, "%s: cannot write\n", output.c_str());
    return 1;
  }
  std::printf("%s: %zu vertices, %zu faces (%s split x%d)\n", output.c_str(),
              om.n_vertices(), om.n_faces(), input.c_str(), times);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 5 && std::string(argv[1]) == "--split") {
    return SplitMain(std::atoi(argv[2]), argv[3], argv[4]);
  }
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr,
                 "usage: scale_meshes [INPUT.off] OUT_DIR\n"
                 "       scale_meshes --split N INPUT OUT.ply\n");
    return 2;
  }
  const std::string input =
      argc == 3 ? argv[1] : std::string(SDCB_MESH_DIR) + "/bunny00.off";
  const std::string out_dir = argv[argc - 1];
  std::filesystem::create_directories(out_dir);
  auto mesh = sdcb::ReadMesh(input);
  if (!mesh.ok()) {
    std::fprintf(stderr, "%s\n", mesh.status().message().c_str());
    return 1;
  }
  struct Level {
    const char* name;
    int loop, sqrt3;
  };
  const Level levels[] = {{"bunny_113k", 0, 1},
                          {"bunny_339k", 0, 2},
                          {"bunny_1m", 0, 3},
                          {"bunny_4m", 1, 3}};
  for (const Level& level : levels) {
    OmMesh om = ToOpenMesh(*mesh);
    if (level.loop > 0) {
      OpenMesh::Subdivider::Uniform::LoopT<OmMesh> loop;
      loop.attach(om);
      loop(level.loop);
      loop.detach();
    }
    OpenMesh::Subdivider::Uniform::Sqrt3T<OmMesh> sqrt3;
    sqrt3.attach(om);
    sqrt3(level.sqrt3);
    sqrt3.detach();
    om.garbage_collection();
    const std::string path = out_dir + "/" + level.name + ".ply";
    if (!WriteBinaryPly(om, path)) {
      std::fprintf(stderr, "%s: cannot write\n", path.c_str());
      return 1;
    }
    std::printf("%s: %zu vertices, %zu faces (Loop x%d, sqrt3 x%d of %s)\n",
                path.c_str(), om.n_vertices(), om.n_faces(), level.loop,
                level.sqrt3, input.c_str());
  }
  return 0;
}
