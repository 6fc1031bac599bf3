// A glTF input kept for writing back (Model::asset): the input document
// with the geometry of its fitted primitives taken out, its scene, names,
// transforms, materials, textures, images and everything else left as the
// file had it, stored as one GLB (the "shell"). Each fitted primitive keeps
// its place, material and mode, its attributes and indices replaced by
// "extras": {"sdcb_parts": [...]}, the model parts whose surfaces it
// becomes. Exporting writes the shell back with those primitives filled
// from the parts' tessellations (EncodeGltfAsset), so that a node used
// several times, a mesh shared by several nodes and every transform stay
// as they were.
#ifndef SDCB_CONVERTERS_GLTF_GLTF_ASSET_H_
#define SDCB_CONVERTERS_GLTF_GLTF_ASSET_H_

#include <string>
#include <string_view>
#include <vector>

#include "sdcb/converters/gltf/gltf_export.h"
#include "sdcb/converters/gltf/gltf_import.h"
#include "sdcb/converters/mesh/surface_mesh.h"
#include "sdcb/core/common/status.h"
#include "sdcb/core/sphere/cube_atlas.h"

namespace sdcb {

// The parts that replace one primitive.
struct GltfFittedPrimitive {
  int mesh = 0;            // glTF mesh index
  int primitive = 0;       // index in its `primitives`
  std::vector<int> parts;  // model parts (0-based), in the order written
  // #K by 3: the triangles of the primitive's kept parts (ModelPart::kept),
  // as indices into its accessors (GltfPrimitive::source_corners' rows, in
  // the file's order); empty when every part of it is fitted. When not
  // empty, the primitive stays as the file had it with these triangles
  // alone, and `parts` go to a new primitive appended to its mesh.
  Eigen::MatrixX3i kept_corners;
  // Its base colour baked into a cube-map atlas of its parts' spheres
  // (converters/gltf/texture_bake.h; tile block k for parts[k]): the PNG's
  // bytes, "" for none.
  std::string atlas_png;
  CubeAtlasLayout atlas_layout;
};

// The shell of `document` with the geometry of `fitted` taken out: those
// primitives lose attributes, indices, morph targets, mode (their surfaces
// are written as TRIANGLES) and the extensions that describe the file's
// triangles (KHR_draco_mesh_compression, FB_ngon_encoding), and hold their
// parts in extras. A primitive with `kept_corners` is split in two: it
// keeps its attributes, material and everything else but those
// extensions, its indices replaced by a new accessor of the kept triangles
// (unsigned short, or unsigned int from 65535 vertices on) and its mode by
// TRIANGLES; a copy of it, its geometry taken out as above, is appended to
// its mesh's primitives and holds the parts. Accessors and buffer views
// nothing uses any more are dropped; every image given by a URI moves into
// a buffer view (its MIME type from the data URI or the file's extension),
// except one whose file was not there, which keeps its URI; all bytes in
// one buffer, the GLB's BIN chunk. kInvalidInput when the document does not
// parse or a primitive, accessor or view it names is not there;
// kUnsupported for a kept primitive whose views are meshopt-compressed;
// kInvalidArgument for kept_corners of a Draco-compressed primitive.
// A fitted primitive with an atlas gets it as an embedded PNG image with a
// texture and sampler (clamp to edge, linear) and a copy of its material
// (a default one if it has none) whose base colour texture is the atlas,
// other textures and the material's extensions dropped; the primitive's
// extras hold "sdcb_atlas": {"tile", "parts", "extent"}, the layout.
// Last, extensionsUsed and extensionsRequired keep only the names that
// some "extensions" object of the shell still has as a key, and
// KHR_mesh_quantization, which no object names (kept primitives may still
// read its accessor types); FB_ngon_encoding listed without any primitive
// naming it (a flag of the whole file) stays only when nothing is fitted.
StatusOr<std::string> MakeGltfShell(
    const GltfDocument& document,
    const std::vector<GltfFittedPrimitive>& fitted);

// The model parts each fitted primitive of `shell` holds (its extras);
// kept_corners empty.
StatusOr<std::vector<GltfFittedPrimitive>> ShellFittedPrimitives(
    std::string_view shell);

// The asset of `shell` with every fitted primitive filled: the meshes of
// its parts (`parts[k]` for part k, in the mesh's local coordinates)
// appended into one, encoded as EncodeGltf does with the options of its
// first part (position bits: the largest of its parts'), its material and
// mode kept. A primitive with an atlas gets TEXCOORD_0 from its parts'
// `directions` (CubeAtlasTexcoords: vertices split where their triangles
// take different cube faces; kInvalidArgument when a part has no
// directions); atlas_primitives counts them and atlas_vertices_beyond_extent
// sums CubeAtlasMesh::corners_beyond_extent. Any other fitted primitive's
// material that samples a texture loses its textures (its surface has no
// texture coordinates), kept in a copy when other primitives use the
// material too; textureless_materials counts them. meshopt writes
// exponential positions (GltfMeshoptPositions::kExponential: no node
// transform, so the asset's nodes stay its own). kInvalidArgument when a
// part index is out of range. extensionsUsed and extensionsRequired as
// MakeGltfShell leaves them, the compression's extensions added.
struct EncodedGltfAsset {
  EncodedGltf gltf;
  int fitted_primitives = 0;
  int textureless_materials = 0;
  int atlas_primitives = 0;
  int atlas_vertices_beyond_extent = 0;
};
StatusOr<EncodedGltfAsset> EncodeGltfAsset(
    std::string_view shell, const std::vector<SurfaceMesh>& parts,
    const std::vector<GltfExportOptions>& options, bool binary);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_GLTF_GLTF_ASSET_H_
