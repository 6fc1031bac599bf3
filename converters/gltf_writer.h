// Writes a triangle mesh as glTF 2.0 (.gltf with embedded buffer, or .glb).
#ifndef SDCB_CONVERTERS_GLTF_WRITER_H_
#define SDCB_CONVERTERS_GLTF_WRITER_H_

#include <string>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

// Writes `mesh` (positions as float32, indices as uint32) to `path`; the
// container is chosen by the extension (.gltf or .glb). Atomic: on failure
// nothing is left at `path`.
Status WriteGltfMesh(const TriangleMesh& mesh, const std::string& path);

// Reads the first triangle primitive of a .gltf/.glb written by
// WriteGltfMesh (or any uncompressed glTF with float positions).
StatusOr<TriangleMesh> ReadGltfMesh(const std::string& path);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_GLTF_WRITER_H_
