// Reads triangle meshes from OBJ, OFF, PLY (ascii and binary) and STL (ascii
// and binary). OpenMesh does the parsing; this layer guards it, because
// OpenMesh 9.0 aborts, hangs or silently drops data on hostile files (see
// docs/INTAKE.md): declared counts are checked against the file size before
// parsing, exceptions are caught, and what was read is compared with what the
// file declared.
#ifndef SDCB_IO_MESH_READER_H_
#define SDCB_IO_MESH_READER_H_

#include <string>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

struct MeshReadInfo {
  int polygons = 0;               // faces in the file before triangulation
  int triangulated_polygons = 0;  // faces with more than three corners
};

// Reads `path`; vertex order is kept (vertex i of the result is the i-th
// vertex of the file, except for STL, which stores no shared vertices: its
// vertices are numbered in order of first appearance). Polygons are
// triangulated as fans from their first corner. Errors (kIoError,
// kCorruptFile, kInvalidInput, kUnsupported) have messages that start with
// the path, e.g. "x.obj: face 12 refers to vertex 900, but the file has 800".
StatusOr<TriangleMesh> ReadMesh(const std::string& path,
                                MeshReadInfo* info = nullptr);

}  // namespace sdcb

#endif  // SDCB_IO_MESH_READER_H_
