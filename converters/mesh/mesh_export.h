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
// standard vertex colors). OpenMesh's OBJ writer rounds the positions to
// float32 before it prints their 17 digits. A mesh with a face that is not
// manifold (a kept part's, core/spline/model.h) is still written: OBJ by
// EncodeObjWithDoubles, PLY and STL with such a face on copies of its
// vertices.
StatusOr<std::string> EncodeSurfaceMesh(const SurfaceMesh& mesh,
                                        const std::string& extension);

// The OBJ in OpenMesh's layout ("# V vertices, F faces", each "v" followed by
// its "vn" when there are normals, then "f a//a b//b c//c"), every vertex and
// face as given and every coordinate the double itself (17 significant
// digits): what a kept part needs to pass through exactly.
std::string EncodeObjWithDoubles(const SurfaceMesh& mesh);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_MESH_MESH_EXPORT_H_
