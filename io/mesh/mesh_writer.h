// Writes a TriangleMesh as OBJ, OFF or PLY (ASCII), chosen by the file
// extension, with optional per-vertex RGB colors (PLY only). Coordinates are
// written with 17 significant digits, so reading the file back gives the
// same doubles. The write is atomic (io/common/atomic_file.h): no half-written
// file.
#ifndef SDCB_IO_MESH_MESH_WRITER_H_
#define SDCB_IO_MESH_MESH_WRITER_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

// #V by 3 colors, one row per vertex, components 0..255.
using VertexColors = Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 3>;

struct MeshWriteOptions {
  // Per-vertex colors, empty for none. Needs a .ply path (kInvalidArgument
  // otherwise) and one row per vertex.
  VertexColors colors;
};

// Writes `mesh` to `path` (.obj, .off or .ply, case-insensitive).
// kInvalidArgument for another extension or colors that do not fit;
// kIoError when the file cannot be written. Messages start with `path`.
Status WriteMesh(const TriangleMesh& mesh, const std::string& path,
                 const MeshWriteOptions& options = {});

}  // namespace sdcb

#endif  // SDCB_IO_MESH_MESH_WRITER_H_
