// Prints the time of the mesh hierarchy and of the whole spherical
// parameterization on CAD-style fans: a double cone, two fans of n
// triangles around the poles over a ring of n vertices (hub valence n).
// The work must grow about linearly in n (it grew with n^2 before the
// hierarchy bounded the valence of removed vertices: > 9 GB at n = 20000).
// Usage: fan_bench [N ...]   (default 2500 5000 10000 20000 40000)
// Peak memory: run `/usr/bin/time -f "%M KB" fan_bench N` per N.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "sdcb/core/mesh/mesh_hierarchy.h"
#include "sdcb/core/param/spherical_parameterization.h"
#include "testing/fan_mesh.h"

namespace {

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes;
  for (int i = 1; i < argc; ++i) sizes.push_back(std::atoi(argv[i]));
  if (sizes.empty()) sizes = {2500, 5000, 10000, 20000, 40000};
  std::printf("%8s %10s %14s %16s\n", "fan n", "faces", "hierarchy s",
              "parameterize s");
  for (int n : sizes) {
    const sdcb::TriangleMesh mesh = sdcb::testing::DoubleCone(n);
    auto start = std::chrono::steady_clock::now();
    auto hierarchy = sdcb::BuildMeshHierarchy(mesh);
    const double hierarchy_seconds = Seconds(start);
    if (!hierarchy.ok()) {
      std::fprintf(stderr, "%s\n", hierarchy.status().message().c_str());
      return 1;
    }
    start = std::chrono::steady_clock::now();
    auto param = sdcb::ParameterizeOnSphere(mesh);
    const double param_seconds = Seconds(start);
    if (!param.ok()) {
      std::fprintf(stderr, "%s\n", param.status().message().c_str());
      return 1;
    }
    std::printf("%8d %10d %14.3f %16.3f\n", n, mesh.num_faces(),
                hierarchy_seconds, param_seconds);
  }
  return 0;
}
