#include "sdcb/io/mesh/mesh_reader.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

#include "sdcb/io/mesh/mesh_parsing.h"

namespace sdcb {
namespace {

namespace fs = std::filesystem;
using mesh_parsing::Num;

// Refuses what is not a regular file: devices, pipes and sockets could be
// endless or block.
Status CheckRegularFile(const std::string& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) return IoError("no such file");
  if (fs::is_directory(st)) return IoError("is a directory, not a mesh file");
  if (!fs::is_regular_file(st)) return IoError("is not a regular file");
  return Status::Ok();
}

}  // namespace

StatusOr<std::string> ReadMeshFileBytes(const std::string& path,
                                        const MeshReadLimits& limits) {
  SDCB_RETURN_IF_ERROR(CheckRegularFile(path));
  std::error_code ec;
  const uintmax_t size = fs::file_size(path, ec);
  if (ec) return IoError("cannot determine the file's size");
  if (size > static_cast<uintmax_t>(
                 std::min(limits.max_file_bytes, limits.max_memory_bytes))) {
    return UnsupportedError(
        "the file has " + Num(size >> 20) + " MB, more than the limit of " +
        Num(std::min(limits.max_file_bytes, limits.max_memory_bytes) >> 20) +
        " MB for mesh files");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return IoError("cannot open the file for reading");
  std::string bytes(static_cast<size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (in.bad() || static_cast<uintmax_t>(in.gcount()) != size) {
    return IoError("reading the file failed");
  }
  return bytes;
}

StatusOr<MeshFileFormat> MeshFileFormatFromPath(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) {
    return static_cast<char>(std::tolower(c));
  });
  if (ext == ".obj") return MeshFileFormat::kObj;
  if (ext == ".off") return MeshFileFormat::kOff;
  if (ext == ".ply") return MeshFileFormat::kPly;
  if (ext == ".stl") return MeshFileFormat::kStl;
  return UnsupportedError("unknown mesh format '" + ext +
                          "' (sdcb reads .obj, .off, .ply and .stl)");
}

StatusOr<TriangleMesh> ReadMeshFromBuffer(std::string_view bytes,
                                          MeshFileFormat format,
                                          MeshReadInfo* info,
                                          const MeshReadLimits& limits) {
  if (bytes.empty()) return CorruptFileError("the file is empty");
  if (format != MeshFileFormat::kStl) {
    // Text formats: a UTF-8 byte-order mark is skipped (else OBJ's first
    // statement would be skipped as unknown); UTF-16 text is refused by
    // name (else it reads as a file without faces).
    if (bytes.substr(0, 3) == "\xEF\xBB\xBF") bytes.remove_prefix(3);
    if (bytes.substr(0, 2) == "\xFE\xFF" || bytes.substr(0, 2) == "\xFF\xFE") {
      return UnsupportedError(
          "the file is UTF-16 text (it starts with a UTF-16 byte-order "
          "mark); sdcb reads ASCII or UTF-8: convert it first (iconv -f "
          "UTF-16 -t UTF-8)");
    }
  }
  // STL merges vertices through a hash map: about 40 bytes per corner.
  mesh_parsing::MeshBuilder builder(limits, bytes.size(),
                                    format == MeshFileFormat::kStl ? 40 : 0);
  Status parsed;
  switch (format) {
    case MeshFileFormat::kOff:
      parsed = mesh_parsing::ParseOff(bytes, limits, &builder);
      break;
    case MeshFileFormat::kObj:
      parsed = mesh_parsing::ParseObj(bytes, limits, &builder);
      break;
    case MeshFileFormat::kPly:
      parsed = mesh_parsing::ParsePly(bytes, limits, &builder);
      break;
    case MeshFileFormat::kStl:
      parsed = mesh_parsing::ParseStl(bytes, limits, &builder);
      break;
  }
  SDCB_RETURN_IF_ERROR(parsed);
  if (builder.num_polygons() == 0) {
    return InvalidInputError("the mesh has no faces");
  }
  return builder.Finish(info);
}

StatusOr<TriangleMesh> ReadMesh(const std::string& path, MeshReadInfo* info,
                                const MeshReadLimits& limits) {
  SDCB_RETURN_IF_ERROR(CheckRegularFile(path).WithPrefix(path));
  StatusOr<MeshFileFormat> format = MeshFileFormatFromPath(path);
  if (!format.ok()) return format.status().WithPrefix(path);
  StatusOr<std::string> bytes = ReadMeshFileBytes(path, limits);
  if (!bytes.ok()) return bytes.status().WithPrefix(path);
  StatusOr<TriangleMesh> mesh =
      ReadMeshFromBuffer(*bytes, *format, info, limits);
  if (!mesh.ok()) return mesh.status().WithPrefix(path);
  return mesh;
}

}  // namespace sdcb
