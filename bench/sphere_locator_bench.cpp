// How fast SphereTriangleLocator (core/sphere/sphere_triangle_locator.h)
// answers: per sphere triangulation, the build time, the cells' size
// (leaves, entries per triangle, longest list), and Locate's time per query
// for two sets of directions: every texel of a one-part cube atlas of tile
// side TILE (the texture bake's queries, uniform on the sphere) and as many
// random points of random triangles (where the triangles are, so crowded
// regions count by their triangles), on one thread, in CPU time (steadier
// than wall time on a shared machine). Then the fraction of texels held and
// an FNV-1a hash of every answer (face and weight bytes), so two builds of
// the locator can be checked to answer identically.
//   sphere_locator_bench [--tile TILE] [SPHERE_MESH ...]
// SPHERE_MESH: a mesh whose vertices are on the unit sphere, e.g. one
// written by `sdcb param MESH -o SPHERE_MESH.off` (rows are normalized).
// Without one: icospheres crowded towards a pole (tests/testing/
// crowded_sphere.h) at scales 1 (uniform), 0.3 and 0.1. TILE defaults to
// 512 (1.6M texels per input).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include "sdcb/core/sphere/cube_atlas.h"
#include "sdcb/core/sphere/sphere_triangle_locator.h"
#include "sdcb/io/mesh/mesh_reader.h"
#include "testing/crowded_sphere.h"

namespace {

struct Input {
  std::string name;
  sdcb::TriangleMesh mesh;
};

double CpuSeconds(std::clock_t start) {
  return static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
}

// FNV-1a over the answers.
struct Hash {
  uint64_t h = 1469598103934665603ull;
  void Add(const sdcb::SphereTriangleLocator::Location& at) {
    Bytes(&at.face, sizeof(at.face));
    Bytes(at.barycentric.data(), 3 * sizeof(double));
  }
  void Bytes(const void* data, size_t bytes) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) {
      h ^= p[i];
      h *= 1099511628211ull;
    }
  }
};

void Run(const Input& in, int tile) {
  const sdcb::TriangleMesh& m = in.mesh;
  std::clock_t start = std::clock();
  const sdcb::SphereTriangleLocator locator(m.vertices, m.faces);
  const double build_ms = 1e3 * CpuSeconds(start);
  const sdcb::SphereTriangleLocator::CellStats stats = locator.Stats();
  // The directions first, so only Locate is timed.
  sdcb::CubeAtlasLayout layout;
  layout.tile = tile;
  std::vector<Eigen::Vector3d> texels, points;
  for (int y = 0; y < layout.height(); ++y) {
    for (int x = 0; x < layout.width(); ++x) {
      texels.push_back(sdcb::CubeAtlasTexelAt(layout, x, y).direction);
    }
  }
  std::mt19937 rng(1);
  std::uniform_int_distribution<int> pick(0, m.num_faces() - 1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (size_t i = 0; i < texels.size(); ++i) {
    const int f = pick(rng);
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c) p += u(rng) * m.vertices.row(m.faces(f, c));
    points.push_back(p);
  }
  Hash hash;
  long held = 0;
  double ns[2];
  for (int set = 0; set < 2; ++set) {
    start = std::clock();
    for (const Eigen::Vector3d& d : set == 0 ? texels : points) {
      const sdcb::SphereTriangleLocator::Location at = locator.Locate(d);
      hash.Add(at);
      held += set == 0 && at.face >= 0;
    }
    ns[set] = 1e9 * CpuSeconds(start) / texels.size();
  }
  std::printf("%-26s %9d %8.1f %8d %7.2f %7d %9zu %9.1f %9.1f %7.4f %016llx\n",
              in.name.c_str(), m.num_faces(), build_ms, stats.leaves,
              static_cast<double>(stats.entries) / m.num_faces(), stats.longest,
              texels.size(), ns[0], ns[1],
              static_cast<double>(held) / texels.size(),
              static_cast<unsigned long long>(hash.h));
}

}  // namespace

int main(int argc, char** argv) {
  int tile = 512;
  std::vector<Input> inputs;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--tile") == 0 && i + 1 < argc) {
      tile = std::max(4, std::atoi(argv[++i]));
      continue;
    }
    sdcb::StatusOr<sdcb::TriangleMesh> mesh = sdcb::ReadMesh(argv[i]);
    if (!mesh.ok()) {
      std::fprintf(stderr, "%s\n", mesh.status().message().c_str());
      return 1;
    }
    mesh->vertices.rowwise().normalize();
    inputs.push_back({argv[i], std::move(*mesh)});
  }
  if (inputs.empty()) {
    for (double scale : {1.0, 0.3, 0.1}) {
      char name[64];
      std::snprintf(name, sizeof(name), "icosphere(5) x %.1f", scale);
      inputs.push_back({name, sdcb::testing::CrowdedIcosphere(5, scale)});
    }
  }
  std::printf("%-26s %9s %8s %8s %7s %7s %9s %9s %9s %7s %16s\n", "sphere mesh",
              "triangles", "build ms", "leaves", "entries", "longest",
              "queries", "ns/texel", "ns/point", "held", "answers' hash");
  std::printf("%-26s %9s %8s %8s %7s %7s %9s %9s %9s %7s %16s\n", "", "",
              "(CPU)", "", "per tri", "list", "per set", "(CPU)", "(CPU)",
              "texels", "");
  for (const Input& in : inputs) Run(in, tile);
  return 0;
}
