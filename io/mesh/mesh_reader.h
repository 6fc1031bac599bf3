// Reads triangle meshes from OBJ, OFF, PLY (ascii, binary little and big
// endian) and STL (ascii and binary). Each format has one guarded parser of
// sdcb's own that builds the mesh itself in a single pass over the bytes (no
// second parser, no temporary files, no paths named inside a file are ever
// opened). Every count is checked against the bytes present and against
// `MeshReadLimits` before anything is allocated; see docs/INTAKE.md.
#ifndef SDCB_IO_MESH_MESH_READER_H_
#define SDCB_IO_MESH_MESH_READER_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

namespace sdcb {

enum class MeshFileFormat { kObj, kOff, kPly, kStl };

// What a read may cost; a file that needs more is refused with a message
// naming the limit (kUnsupported) before the memory is allocated. The
// defaults suit meshes up to about 50 million triangles.
struct MeshReadLimits {
  // Size of the file (ReadMesh only; a buffer is already in memory).
  int64_t max_file_bytes = int64_t{4} << 30;
  // Vertices and triangles (after triangulating polygons); at most 2^31 - 1
  // because TriangleMesh indices are int.
  int64_t max_vertices = 200'000'000;
  int64_t max_triangles = 200'000'000;
  // Corners of one polygon.
  int64_t max_polygon_corners = 100'000;
  // Estimated peak memory of the read: the file's bytes plus twice the
  // mesh arrays (24 bytes per vertex, 12 per triangle: the parse and the
  // result) plus, for STL, 40 bytes per corner for merging vertices.
  int64_t max_memory_bytes = int64_t{8} << 30;
};

struct MeshReadInfo {
  int polygons = 0;               // faces in the file before triangulation
  int triangulated_polygons = 0;  // faces with more than three corners
  // What was read despite not following the format, one sentence each
  // without the file name, e.g. "line 3 of the header ('Created by
  // Blender3D 247') is not a PLY keyword line; ignored". The library never
  // prints them; the CLI does.
  std::vector<std::string> warnings;
};

// The format named by the extension of `path` (.obj .off .ply .stl, any
// case), else kUnsupported.
StatusOr<MeshFileFormat> MeshFileFormatFromPath(const std::string& path);

// Parses a whole file held in memory. Vertex order is kept (vertex i of the
// result is the i-th vertex of the file, except for STL, which stores no
// shared vertices: its vertices are numbered in order of first appearance,
// exactly equal positions merged). Polygons are triangulated as fans from
// their first corner, except non-convex ones (of at most 64 corners), which
// are ear-clipped in their plane so no triangle is inverted. OFF, OBJ and PLY
// skip a UTF-8 byte-order mark and refuse UTF-16 text. Coordinates are
// parsed as doubles (text: locale-independent, decimal or hexadecimal; binary:
// the stored type). Errors (kCorruptFile, kInvalidInput, kUnsupported) are one
// sentence without a file name, e.g. "line 12: face 3 refers to vertex 900, but
// the file has 800 vertices (OBJ indices run from 1)".
StatusOr<TriangleMesh> ReadMeshFromBuffer(std::string_view bytes,
                                          MeshFileFormat format,
                                          MeshReadInfo* info = nullptr,
                                          const MeshReadLimits& limits = {});

// The bytes of the regular file `path`: directories, devices, FIFOs and
// sockets are refused (kIoError; they can be endless or block), and so is a
// file beyond limits.max_file_bytes or max_memory_bytes (kUnsupported).
// Errors without the path. ReadMesh reads through it, and so does the glTF
// reader (converters/gltf/gltf_import.h).
StatusOr<std::string> ReadMeshFileBytes(const std::string& path,
                                        const MeshReadLimits& limits = {});

// Reads the regular file `path` in the format of its extension (through
// ReadMeshFromBuffer). Errors (also kIoError) have messages that start with
// the path, e.g. "x.obj: line 12: face 3 refers to vertex 900, ...".
StatusOr<TriangleMesh> ReadMesh(const std::string& path,
                                MeshReadInfo* info = nullptr,
                                const MeshReadLimits& limits = {});

}  // namespace sdcb

#endif  // SDCB_IO_MESH_MESH_READER_H_
