// Gathers glTF documents of one mesh each (EncodeGltf's GLBs, in any of its
// encodings) into one document: the glTF writers' shared step for files of
// several parts (EncodeGltfParts) and for an input asset written back with
// its fitted primitives replaced (EncodeGltfAsset).
#ifndef SDCB_CONVERTERS_GLTF_GLTF_GATHER_H_
#define SDCB_CONVERTERS_GLTF_GLTF_GATHER_H_

#include <nlohmann/json.hpp>
#include <string>

#include "sdcb/converters/gltf/gltf_export.h"
#include "sdcb/core/common/status.h"

namespace sdcb {

class GltfGather {
 public:
  // Starts from the document `json`, whose buffer 0 (made if missing) holds
  // `bin`: the BIN chunk of a GLB.
  GltfGather(nlohmann::ordered_json json, std::string bin);

  // Appends the buffer views and accessors of the one mesh of `encoded` (a
  // GLB of EncodeGltf), its BIN chunk to buffer 0 and its other buffers
  // (meshopt's fallback) after the document's, and merges its extensions
  // used and required. Returns its mesh, not appended: the primitives'
  // accessor and Draco view indices rebased; their material appended and
  // rebased with `keep_materials`, else dropped. node() is then the node
  // EncodeGltf wrote for it, without its mesh (meshopt's dequantizing
  // translation and scale with quantized positions, or nothing).
  StatusOr<nlohmann::ordered_json> AppendMesh(const EncodedGltf& encoded,
                                              bool keep_materials);

  nlohmann::ordered_json& json() { return json_; }
  const nlohmann::ordered_json& node() const { return node_; }

  // The file: a GLB (`binary`) or a .gltf with buffer 0 as a data URI; the
  // top-level keys in glTF's usual order, empty arrays left out. The
  // result's errors, step and exponential bits are the largest of the
  // meshes appended.
  EncodedGltf Finish(bool binary);

 private:
  nlohmann::ordered_json json_;
  std::string bin_;
  nlohmann::ordered_json node_;
  GltfExportResult result_;
};

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_GLTF_GLTF_GATHER_H_
