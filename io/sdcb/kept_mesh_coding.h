// INTERNAL to io/sdcb/sdcb_model_file.cpp (installed with the other headers,
// not an API): a kept part's triangles (core/spline/model.h, KeptMesh::mesh)
// as a version 4 PART's `HEAD` and `KEPT` payloads (docs/FORMAT.md, "Kept
// parts"), losslessly, with meshoptimizer's vertex and index codecs.
//
// Positions: meshoptimizer's vertex codec works on fixed-size vertices; a
// vertex is stored as its three float32 (12 bytes) when every coordinate of
// the mesh is exactly a float (binary STL, most PLY), else as its three
// doubles (24 bytes); either way the decoded doubles are the input's, bit for
// bit. Triangles: meshoptimizer's index codec may rotate a triangle's three
// indices (a, b, c) -> (b, c, a) (the winding is kept); the rotation of each
// triangle is stored beside it, so the faces come back as they were.
#ifndef SDCB_IO_SDCB_KEPT_MESH_CODING_H_
#define SDCB_IO_SDCB_KEPT_MESH_CODING_H_

#include <cstddef>
#include <string>
#include <string_view>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb::sdcb_internal {

// A kept part's HEAD (counts and position form) and KEPT (the encoded
// streams) payloads.
struct KeptMeshPayloads {
  std::string head;
  std::string kept;
};

// `mesh` must have at least one face, indices in range and fewer than 2^31
// vertices and faces (ValidateModel checks a kept part).
KeptMeshPayloads EncodeKeptMesh(const TriangleMesh& mesh);

// The mesh of a kept part's HEAD and KEPT payloads; kCorruptFile naming the
// problem. Counts are checked against `file_size` before anything is
// allocated for them.
StatusOr<TriangleMesh> DecodeKeptMesh(std::string_view head,
                                      std::string_view kept, size_t file_size);

}  // namespace sdcb::sdcb_internal

#endif  // SDCB_IO_SDCB_KEPT_MESH_CODING_H_
