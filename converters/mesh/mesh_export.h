// Encodes a SurfaceMesh as OBJ (with normals), PLY (binary, normals and
// colors) or STL (binary) through OpenMesh's writers.
#ifndef SDCB_CONVERTERS_MESH_MESH_EXPORT_H_
#define SDCB_CONVERTERS_MESH_MESH_EXPORT_H_

#include <string>

#include "sdcb/converters/mesh/surface_mesh.h"
#include "sdcb/core/common/status.h"

namespace sdcb {

// The bytes of `mesh` as an OBJ (text), PLY or STL (binary) file;
// `extension` is ".obj", ".ply" or ".stl" (case-insensitive; else
// kInvalidArgument). OBJ stores 17 significant digits; PLY and STL store
// float32 coordinates. Colors are written to PLY only (OBJ and STL have no
// standard vertex colors). kInvalidInput for a face that is not manifold.
StatusOr<std::string> EncodeSurfaceMesh(const SurfaceMesh& mesh,
                                        const std::string& extension);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_MESH_MESH_EXPORT_H_
