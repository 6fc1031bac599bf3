// Reads glTF 2.0 (.gltf with external or data-URI buffers, .glb) into the
// default scene's node hierarchy and its triangle primitives, each a
// TriangleMesh in its mesh's local frame with vertices merged by exactly
// equal position (UV and normal seams are not holes). Decodes
// KHR_draco_mesh_compression (Draco's decoder), EXT_meshopt_compression
// (libmeshoptimizer's codecs and filters) and the accessor types of
// KHR_mesh_quantization. The JSON's types are checked against the glTF 2.0
// schema (gltf_schema_check.h) before tinygltf parses it; every accessor,
// buffer view and index is checked against the bytes present, and every
// count against MeshReadLimits, before anything is allocated for it. See
// docs/INTAKE.md ("glTF").
#ifndef SDCB_CONVERTERS_GLTF_GLTF_IMPORT_H_
#define SDCB_CONVERTERS_GLTF_GLTF_IMPORT_H_

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/io/mesh/mesh_reader.h"

namespace sdcb {

// One node of the file (glTF `nodes[i]`); indices are the file's (0-based).
struct GltfNode {
  std::string name;  // "" when the file gives none
  int mesh = -1;     // glTF mesh index, -1 for none
  std::vector<int> children;
  // The local transform, column vectors (p_parent = local * p_node): the
  // node's `matrix` (column-major in the file), else T * R * S.
  Eigen::Matrix4d local = Eigen::Matrix4d::Identity();
};

// One triangle primitive (TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN) of a
// mesh the scene uses.
struct GltfPrimitive {
  int mesh = 0;       // glTF mesh index
  int primitive = 0;  // index in the mesh's `primitives`
  // The mesh's name ("mesh N" when it has none), with "#k" (k = primitive)
  // appended when the mesh has several primitives.
  std::string name;
  int material = -1;  // glTF material index, -1 for none
  // In the mesh's local frame (no node transform applied). Vertices merged
  // by exactly equal position (-0 = +0), numbered in order of first use by
  // the triangles; vertices no triangle uses are dropped, and so are
  // triangles with two corners at one position (strip restarts).
  TriangleMesh triangles;
  // Per corner, #F*3 rows (row 3f+k is corner k of face f), empty when the
  // primitive has no TEXCOORD_0 / COLOR_0: a merged vertex can carry
  // several. Texture coordinates as stored (u right, v down); colours RGBA
  // in 0..1 (alpha 1 for a VEC3 COLOR_0).
  Eigen::MatrixX2d texcoords;
  Eigen::MatrixX4d colors;
  // #F by 3: row f holds, for each corner of face f of `triangles`, the
  // index of its vertex in the primitive's accessors (the file's numbering,
  // before merging by position; strips and fans as their triangles, the
  // dropped triangles left out). Empty when the primitive's vertices are
  // Draco- or meshopt-compressed: new indices into the file's accessors
  // would then need the data decoded and written again.
  Eigen::MatrixX3i source_corners;
  int source_vertices = 0;     // POSITION count before merging
  int dropped_degenerate = 0;  // triangles dropped (two corners merged)
};

// The bytes of a glTF file as read (what MakeGltfShell keeps of it): its JSON
// text, the data of every buffer (external files and data URIs resolved, a
// GLB's BIN chunk for its buffer without a URI) and, per image, its encoded
// bytes when the image is given by a URI, a file's or a data URI ("" for
// one in a buffer view).
struct GltfDocument {
  std::string json;
  std::vector<std::string> buffers;
  std::vector<std::string> images;
};

struct GltfAsset {
  std::vector<GltfNode> nodes;  // every node of the file, in file order
  int scene = 0;                // the scene read: `scene`, else 0
  std::vector<int> roots;       // that scene's root nodes
  // The triangle primitives of every mesh a node of the scene uses (each
  // mesh once, however many nodes use it), by mesh, then primitive index.
  std::vector<GltfPrimitive> primitives;
  int point_primitives = 0;  // POINTS primitives skipped
  int line_primitives = 0;   // LINES, LINE_LOOP, LINE_STRIP skipped
  GltfDocument document;
};

// Parses a whole .glb (bytes starting with "glTF") or .gltf held in memory.
// Buffers must be in the GLB's BIN chunk or data URIs: a buffer naming an
// external file is an error (no file is ever opened). Errors are one
// sentence without a file name that names the element, e.g. "primitive 0 of
// mesh 2: index 900 refers past the 24 vertices" (kInvalidInput for content
// glTF forbids: indices out of range, non-finite positions, node cycles, no
// scene, no triangles; kCorruptFile for bytes that do not match: accessors
// past their buffer views, wrong component types, undecodable Draco or
// meshopt data, JSON types the schema forbids, tinygltf's JSON errors;
// kUnsupported beyond `limits`).
StatusOr<GltfAsset> ReadGltfFromBuffer(std::string_view bytes,
                                       const MeshReadLimits& limits = {});

// Reads the regular file `path` (.gltf or .glb), external buffers from
// regular files under its directory. Errors start with the path.
StatusOr<GltfAsset> ReadGltf(const std::string& path,
                             const MeshReadLimits& limits = {});

// Every primitive of `asset` in one mesh, in order (primitive i's vertices
// and faces after those of 0..i-1, none shared), in mesh-local
// coordinates. face_primitive (if not null) receives, per face, the index
// into asset.primitives it came from.
TriangleMesh ConcatenatePrimitives(const GltfAsset& asset,
                                   std::vector<int>* face_primitive = nullptr);

// True if `path` ends in .gltf or .glb (any case).
bool IsGltfPath(const std::string& path);

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_GLTF_GLTF_IMPORT_H_
