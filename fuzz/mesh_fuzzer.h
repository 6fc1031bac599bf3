// The body shared by the mesh-format fuzzers: parse the bytes as one format;
// an accepted mesh must be well formed (finite coordinates, indices in
// range) and go through the topology analysis `sdcb check` runs.
#ifndef SDCB_FUZZ_MESH_FUZZER_H_
#define SDCB_FUZZ_MESH_FUZZER_H_

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/io/mesh/mesh_reader.h"

inline int FuzzMeshFormat(const uint8_t* data, size_t size,
                          sdcb::MeshFileFormat format) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  sdcb::MeshReadInfo info;
  const sdcb::StatusOr<sdcb::TriangleMesh> mesh =
      sdcb::ReadMeshFromBuffer(bytes, format, &info);
  if (!mesh.ok()) {
    if (mesh.status().message().empty()) __builtin_trap();
    return 0;
  }
  if (mesh->num_faces() == 0 || !mesh->vertices.allFinite() ||
      info.polygons > mesh->num_faces()) {
    __builtin_trap();
  }
  for (int f = 0; f < mesh->num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh->faces(f, k);
      if (v < 0 || v >= mesh->num_vertices()) __builtin_trap();
    }
  }
  if (!sdcb::AnalyzeMeshTopology(*mesh).ok()) __builtin_trap();
  return 0;
}

#endif  // SDCB_FUZZ_MESH_FUZZER_H_
