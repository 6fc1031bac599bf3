// libFuzzer harness: the glTF reader's buffer entry point
// (converters/gltf/gltf_import.h), .glb or .gltf. A refusal is one sentence;
// an accepted asset has well-formed primitives (finite coordinates, indices
// in range, one texture coordinate and colour row per corner) that go
// through the topology analysis `sdcb check` runs.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "sdcb/converters/gltf/gltf_import.h"
#include "sdcb/core/mesh/mesh_topology.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  sdcb::MeshReadLimits limits;
  limits.max_memory_bytes = int64_t{512} << 20;  // under -rss_limit_mb=2048
  const sdcb::StatusOr<sdcb::GltfAsset> asset =
      sdcb::ReadGltfFromBuffer(bytes, limits);
  if (!asset.ok()) {
    const std::string& message = asset.status().message();
    if (message.empty() || message.find('\n') != std::string::npos) {
      __builtin_trap();
    }
    return 0;
  }
  if (asset->primitives.empty()) __builtin_trap();
  for (const sdcb::GltfPrimitive& p : asset->primitives) {
    const sdcb::TriangleMesh& mesh = p.triangles;
    if (mesh.num_faces() == 0 || !mesh.vertices.allFinite()) __builtin_trap();
    if (!sdcb::CheckFaceIndices(mesh).ok()) __builtin_trap();
    const Eigen::Index corners = 3 * Eigen::Index{mesh.num_faces()};
    if ((p.texcoords.rows() != 0 && p.texcoords.rows() != corners) ||
        (p.colors.rows() != 0 && p.colors.rows() != corners)) {
      __builtin_trap();
    }
  }
  for (const sdcb::GltfNode& node : asset->nodes) {
    for (const int child : node.children) {
      if (child < 0 || child >= static_cast<int>(asset->nodes.size())) {
        __builtin_trap();
      }
    }
  }
  const sdcb::TriangleMesh all = sdcb::ConcatenatePrimitives(*asset);
  if (!sdcb::AnalyzeMeshTopology(all).ok()) __builtin_trap();
  return 0;
}
