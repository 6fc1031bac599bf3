// Writes a SurfaceMesh as glTF 2.0 (.gltf with the buffer embedded as a data
// URI, or .glb): one mesh, one node, one scene, asset generator "sdcb" (or
// several meshes, one node each: EncodeGltfParts);
// POSITION (with min / max), NORMAL, COLOR_0 when the mesh has colors,
// TEXCOORD_0 when it has texture coordinates (Draco quantizes them to 15
// bits, meshopt to normalized unsigned shorts), and triangle indices. Three
// encodings:
//   - plain: float32 attributes through tinygltf;
//   - Draco: KHR_draco_mesh_compression (a required extension) through
//     Draco's glTF encoder, positions quantized to `position_bits` over the
//     largest side of the bounding box, compression level `draco_level`;
//   - meshopt: EXT_meshopt_compression and, where shorts hold positions or
//     normals, KHR_mesh_quantization (both required): vertex cache and fetch
//     order optimized, positions stored as `meshopt_positions` says (below),
//     normals as normalized shorts, colors as normalized bytes, texture
//     coordinates (in [0, 1]) as normalized unsigned shorts, buffers encoded
//     with libmeshoptimizer (index codec version 1) and a fallback buffer
//     without data.
// The write is atomic.
#ifndef SDCB_CONVERTERS_GLTF_GLTF_EXPORT_H_
#define SDCB_CONVERTERS_GLTF_GLTF_EXPORT_H_

#include <cstdint>
#include <string>
#include <vector>

#include "sdcb/converters/mesh/surface_mesh.h"
#include "sdcb/core/common/status.h"

namespace sdcb {

enum class GltfCompression { kNone, kDraco, kMeshopt };

// How meshopt stores POSITION.
enum class GltfMeshoptPositions {
  // Unsigned shorts on the grid of `position_bits` over the bounding box,
  // the node's translation and uniform scale undoing the quantization (a
  // file of its own: the node is the encoder's).
  kQuantized,
  // Floats through EXT_meshopt_compression's EXPONENTIAL filter (stride 12,
  // one exponent per position, K-bit mantissas), no node transform (for
  // meshes whose nodes are someone else's, a glTF asset's). K is the fewest
  // bits (1..23) whose decoded positions are within the error of the
  // `position_bits` grid, sqrt(3) / 2 * QuantizationStep, of the exact ones;
  // where 23 bits are not enough, the floats are stored as they are
  // (filter NONE).
  kExponential,
};

struct GltfExportOptions {
  GltfCompression compression = GltfCompression::kNone;
  // Position quantization (Draco: 1..30; meshopt: 1..16). meshopt's
  // exponential positions keep the error of this grid (above).
  int position_bits = 14;
  GltfMeshoptPositions meshopt_positions = GltfMeshoptPositions::kQuantized;
  // Draco compression level, 0 (fastest) .. 10 (smallest).
  int draco_level = 7;
};

struct GltfExportResult {
  int64_t bytes = 0;  // size of the written file
  // Largest distance between a stored and an exact vertex position caused by
  // quantization (0 for float32 storage, whose rounding is reported as
  // float32_error instead). meshopt's exponential positions: the largest
  // distance between a decoded and an exact position, measured (float32
  // rounding included).
  double quantization_error = 0.0;
  // Grid spacing, 0 without quantization; exponential positions: the
  // largest of their vectors' spacings 2^exponent.
  double quantization_step = 0.0;
  double float32_error = 0.0;  // largest float32 rounding of a position
  // meshopt's exponential positions: the mantissa bits K (24: stored
  // unfiltered); 0 otherwise.
  int exponential_bits = 0;
};

// The quantization grid of `bits` bits over the largest side of the
// bounding box of `positions` (#V by 3): spacing range / (2^bits - 1).
double QuantizationStep(const Eigen::MatrixX3d& positions, int bits);

// The fewest bits (at most `max_bits`) whose quantization error,
// sqrt(3) / 2 * QuantizationStep, is at most `max_error`.
int PositionBitsFor(const Eigen::MatrixX3d& positions, double max_error,
                    int max_bits);

// The file's bytes and what the encoding did to the positions.
struct EncodedGltf {
  std::string bytes;
  GltfExportResult result;  // result.bytes == bytes.size()
};

// `mesh` as a .glb (`binary`) or a .gltf with its buffer embedded.
// kInvalidArgument for bits out of range, normals that are not unit
// vectors, or texture coordinates outside [0, 1] with meshopt.
StatusOr<EncodedGltf> EncodeGltf(const SurfaceMesh& mesh,
                                 const GltfExportOptions& options, bool binary);

// Several meshes in one file: mesh i encoded as EncodeGltf encodes it alone
// with options[i] (its own quantization), then all of them gathered into
// one buffer with one node and one mesh per part, both named names[i], and
// one scene of every node. `meshes`, `names` and `options` have the same
// size >= 1 (else kInvalidArgument). The result's errors, step and
// exponential bits are the largest over the meshes; bytes the file's.
StatusOr<EncodedGltf> EncodeGltfParts(
    const std::vector<SurfaceMesh>& meshes,
    const std::vector<std::string>& names,
    const std::vector<GltfExportOptions>& options, bool binary);

// EncodeGltf written to `path`, which ends in .gltf or .glb (else
// kInvalidArgument); kIoError if the file cannot be written (nothing is left
// at `path`).
StatusOr<GltfExportResult> WriteGltf(const SurfaceMesh& mesh,
                                     const GltfExportOptions& options,
                                     const std::string& path);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_GLTF_GLTF_EXPORT_H_
