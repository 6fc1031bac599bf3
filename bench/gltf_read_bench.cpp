// How long ReadGltf takes (converters/gltf/gltf_import.h): each FILE read
// REPEATS times (default 5), the median wall time printed with what was
// read (primitives, POSITION count, merged vertices, triangles).
//   gltf_read_bench FILE... [--repeats N]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "sdcb/converters/gltf/gltf_import.h"
#include "sdcb/core/common/stopwatch.h"

int main(int argc, char** argv) {
  std::vector<std::string> files;
  int repeats = 5;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--repeats" && i + 1 < argc) {
      repeats = std::max(1, std::atoi(argv[++i]));
    } else {
      files.push_back(a);
    }
  }
  std::printf("%-28s %10s %10s %10s %10s %10s\n", "file", "median ms",
              "primitives", "source v", "merged v", "triangles");
  for (const std::string& file : files) {
    std::vector<double> ms;
    sdcb::StatusOr<sdcb::GltfAsset> asset = sdcb::GltfAsset();
    for (int r = 0; r < repeats; ++r) {
      const sdcb::Stopwatch clock;
      asset = sdcb::ReadGltf(file);
      ms.push_back(1e3 * clock.Seconds());
    }
    if (!asset.ok()) {
      std::printf("%s: %s\n", file.c_str(), asset.status().message().c_str());
      continue;
    }
    std::sort(ms.begin(), ms.end());
    long long source = 0, merged = 0, triangles = 0;
    for (const sdcb::GltfPrimitive& p : asset->primitives) {
      source += p.source_vertices;
      merged += p.triangles.num_vertices();
      triangles += p.triangles.num_faces();
    }
    const std::string name = file.substr(file.find_last_of('/') + 1);
    std::printf("%-28s %10.1f %10zu %10lld %10lld %10lld\n", name.c_str(),
                ms[ms.size() / 2], asset->primitives.size(), source, merged,
                triangles);
  }
  return 0;
}
