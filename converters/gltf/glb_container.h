// The GLB container (glTF 2.0 spec, "Binary glTF Layout"): a 12-byte header
// ("glTF", version 2, total length), a JSON chunk, an optional BIN chunk.
// Shared by the glTF writer and reader.
#ifndef SDCB_CONVERTERS_GLTF_GLB_CONTAINER_H_
#define SDCB_CONVERTERS_GLTF_GLB_CONTAINER_H_

#include <string>
#include <string_view>

#include "sdcb/core/common/status.h"

namespace sdcb {

// Appends `fill` until the size of `s` is a multiple of 4 (glTF aligns
// chunks and buffer views to 4 bytes).
void Pad4(std::string* s, char fill);

// A GLB of the JSON text (padded with spaces) and, unless empty, the BIN
// chunk (padded with zeros).
std::string PackGlb(std::string json_text, std::string bin);

// Views into a GLB's bytes.
struct GlbChunks {
  std::string_view json;
  std::string_view bin;  // empty when the file has no BIN chunk
};

// Splits `glb` into its chunks: magic "glTF", version 2, a JSON chunk first
// and, if present, a BIN chunk next, each within the bytes. kCorruptFile
// with one sentence otherwise (a length beyond the file names both).
StatusOr<GlbChunks> SplitGlb(std::string_view glb);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_GLTF_GLB_CONTAINER_H_
