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

namespace sdcb {

// The parts that replace one primitive.
struct GltfFittedPrimitive {
  int mesh = 0;       // glTF mesh index
  int primitive = 0;  // index in its `primitives`
  std::vector<int> parts;  // model parts (0-based), in the order written
};

// The shell of `document` with the geometry of `fitted` taken out: those
// primitives lose attributes, indices, morph targets and Draco data, and
// hold their parts in extras; accessors and buffer views nothing uses any
// more are dropped; every image given by a URI moves into a buffer view
// (its MIME type from the data URI or the file's extension), except one
// whose file was not there, which keeps its URI; all bytes in
// one buffer, the GLB's BIN chunk. kInvalidInput when the document does
// not parse or a primitive, accessor or view it names is not there;
// kUnsupported for a kept primitive whose views are meshopt-compressed.
StatusOr<std::string> MakeGltfShell(
    const GltfDocument& document,
    const std::vector<GltfFittedPrimitive>& fitted);

// The model parts each fitted primitive of `shell` holds (its extras).
StatusOr<std::vector<GltfFittedPrimitive>> ShellFittedPrimitives(
    std::string_view shell);

// The asset of `shell` with every fitted primitive filled: the meshes of
// its parts (`parts[k]` for part k, in the mesh's local coordinates)
// appended into one, encoded as EncodeGltf does with the options of its
// first part (position bits: the largest of its parts'), its material and
// mode kept. A fitted primitive's material that samples a texture loses
// its textures (a fitted surface carries no texture coordinates), kept in a
// copy when other primitives use the material too; textureless_materials
// counts them. kUnsupported for meshopt (its dequantizing node transform
// would replace the asset's nodes'); kInvalidArgument when a part index is
// out of range.
struct EncodedGltfAsset {
  EncodedGltf gltf;
  int fitted_primitives = 0;
  int textureless_materials = 0;
};
StatusOr<EncodedGltfAsset> EncodeGltfAsset(
    std::string_view shell, const std::vector<SurfaceMesh>& parts,
    const std::vector<GltfExportOptions>& options, bool binary);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_GLTF_GLTF_ASSET_H_
