// The JSON types the glTF 2.0 schema (specification/2.0/schema/*.schema.json)
// gives the properties of the core objects: the top-level arrays (accessors
// with sparse, animations with channels and samplers, buffers, bufferViews,
// cameras, images, materials with pbrMetallicRoughness and their texture
// infos, meshes with primitives, attributes and targets, nodes, samplers,
// scenes, skins, textures), asset, scene and extensionsUsed /
// extensionsRequired. Checked: objects, arrays, strings (`name`, `uri`, ...),
// numbers (factors, matrices), booleans, integers, and glTF ids (indices) as
// integers >= 0 (a number with a zero fraction counts as an integer, as in
// JSON Schema); in every object, `extensions` is an object and each
// extension's value an object. Unknown properties and `extras` may be
// anything (the spec allows them); required properties, enumerations,
// ranges and whether an index refers to an element are left to the reader.
// tinygltf takes many properties of the wrong type as absent without a
// word; this check refuses such a file instead.
#ifndef SDCB_CONVERTERS_GLTF_GLTF_SCHEMA_CHECK_H_
#define SDCB_CONVERTERS_GLTF_GLTF_SCHEMA_CHECK_H_

#include <nlohmann/json_fwd.hpp>

#include "sdcb/core/common/status.h"

namespace sdcb {

// Ok when every property of `root` (the parsed JSON of a .gltf or of a
// GLB's JSON chunk) that the schema types has its type. Otherwise
// kCorruptFile naming the first mismatch, in the order of the schema's
// properties, by its JSON path: "materials[0].pbrMetallicRoughness.
// baseColorTexture.index is -1, not a non-negative integer (glTF 2.0
// schema)". String values and odd keys are shown JSON-quoted and cut to 40
// bytes, so the message is one line.
Status CheckGltfSchemaTypes(const nlohmann::json& root);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_GLTF_GLTF_SCHEMA_CHECK_H_
