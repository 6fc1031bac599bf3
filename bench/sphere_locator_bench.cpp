// How fast SphereTriangleLocator (core/sphere/sphere_triangle_locator.h)
// answers the texture bake's queries: per sphere triangulation, the build
// time and one Locate per texel of a one-part cube atlas of tile side TILE
// (the bake's directions), on one thread (CPU seconds: steadier than wall
// time on a shared machine), with the fraction of texels held
// and an FNV-1a hash of every answer (face and weight bytes), so two builds
// of the locator can be checked to answer identically.
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

void Hash(const void* data, size_t bytes, uint64_t* h) {
  const unsigned char* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) {
    *h ^= p[i];
    *h *= 1099511628211ull;
  }
}

double CpuSeconds(std::clock_t start) {
  return static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
}

void Run(const Input& in, int tile) {
  std::clock_t start = std::clock();
  const sdcb::SphereTriangleLocator locator(in.mesh.vertices, in.mesh.faces);
  const double build_ms = 1e3 * CpuSeconds(start);
  sdcb::CubeAtlasLayout layout;
  layout.tile = tile;
  uint64_t hash = 1469598103934665603ull;
  long held = 0;
  start = std::clock();
  for (int y = 0; y < layout.height(); ++y) {
    for (int x = 0; x < layout.width(); ++x) {
      const sdcb::CubeAtlasTexel texel = sdcb::CubeAtlasTexelAt(layout, x, y);
      const sdcb::SphereTriangleLocator::Location at =
          locator.Locate(texel.direction);
      Hash(&at.face, sizeof(at.face), &hash);
      Hash(at.barycentric.data(), 3 * sizeof(double), &hash);
      held += at.face >= 0;
    }
  }
  const double seconds = CpuSeconds(start);
  const double texels = static_cast<double>(layout.width()) * layout.height();
  std::printf("%-28s %9d %9.1f %9.0f %9.3f %9.1f %7.4f %016llx\n",
              in.name.c_str(), in.mesh.num_faces(), build_ms, texels, seconds,
              1e9 * seconds / texels, held / texels,
              static_cast<unsigned long long>(hash));
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
  std::printf("%-28s %9s %9s %9s %9s %9s %7s %16s\n", "sphere mesh",
              "triangles", "build ms", "texels", "locate s", "ns/texel", "held",
              "answers' hash");
  for (const Input& in : inputs) Run(in, tile);
  return 0;
}
