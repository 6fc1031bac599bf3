#include "sdcb/io/mesh/mesh_writer.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <ostream>

#include "sdcb/io/common/atomic_file.h"

namespace sdcb {
namespace {

enum class MeshFormat { kObj, kOff, kPly, kUnknown };

MeshFormat FormatOf(const std::string& path) {
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos) return MeshFormat::kUnknown;
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) {
    return static_cast<char>(std::tolower(c));
  });
  if (ext == "obj") return MeshFormat::kObj;
  if (ext == "off") return MeshFormat::kOff;
  if (ext == "ply") return MeshFormat::kPly;
  return MeshFormat::kUnknown;
}

// "x y z" with round-trip precision.
std::string Coordinates(const TriangleMesh& mesh, int v) {
  char buffer[96];
  std::snprintf(buffer, sizeof(buffer), "%.17g %.17g %.17g",
                mesh.vertices(v, 0), mesh.vertices(v, 1), mesh.vertices(v, 2));
  return buffer;
}

void WriteObj(const TriangleMesh& mesh, std::ostream& out) {
  out << "# written by sdcb\n";
  for (int v = 0; v < mesh.num_vertices(); ++v)
    out << "v " << Coordinates(mesh, v) << "\n";
  for (int f = 0; f < mesh.num_faces(); ++f) {
    out << "f " << mesh.faces(f, 0) + 1 << " " << mesh.faces(f, 1) + 1 << " "
        << mesh.faces(f, 2) + 1 << "\n";
  }
}

void WriteOff(const TriangleMesh& mesh, std::ostream& out) {
  out << "OFF\n" << mesh.num_vertices() << " " << mesh.num_faces() << " 0\n";
  for (int v = 0; v < mesh.num_vertices(); ++v)
    out << Coordinates(mesh, v) << "\n";
  for (int f = 0; f < mesh.num_faces(); ++f) {
    out << "3 " << mesh.faces(f, 0) << " " << mesh.faces(f, 1) << " "
        << mesh.faces(f, 2) << "\n";
  }
}

void WritePly(const TriangleMesh& mesh, const VertexColors& colors,
              std::ostream& out) {
  const bool with_colors = colors.rows() > 0;
  out << "ply\nformat ascii 1.0\ncomment written by sdcb\n"
      << "element vertex " << mesh.num_vertices() << "\n"
      << "property double x\nproperty double y\nproperty double z\n";
  if (with_colors) {
    out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  }
  out << "element face " << mesh.num_faces() << "\n"
      << "property list uchar int vertex_indices\nend_header\n";
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    out << Coordinates(mesh, v);
    if (with_colors) {
      out << " " << int{colors(v, 0)} << " " << int{colors(v, 1)} << " "
          << int{colors(v, 2)};
    }
    out << "\n";
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    out << "3 " << mesh.faces(f, 0) << " " << mesh.faces(f, 1) << " "
        << mesh.faces(f, 2) << "\n";
  }
}

}  // namespace

Status WriteMesh(const TriangleMesh& mesh, const std::string& path,
                 const MeshWriteOptions& options) {
  const MeshFormat format = FormatOf(path);
  if (format == MeshFormat::kUnknown) {
    return InvalidArgumentError(
        path + ": unknown mesh extension (use .obj, .off or .ply)");
  }
  if (options.colors.rows() > 0) {
    if (format != MeshFormat::kPly) {
      return InvalidArgumentError(path + ": vertex colors need a .ply file");
    }
    if (options.colors.rows() != mesh.num_vertices()) {
      return InvalidArgumentError(
          path + ": " + std::to_string(options.colors.rows()) + " colors for " +
          std::to_string(mesh.num_vertices()) + " vertices");
    }
  }
  return WriteFileAtomically(
      [&](std::ostream& out) {
        switch (format) {
          case MeshFormat::kObj:
            WriteObj(mesh, out);
            break;
          case MeshFormat::kOff:
            WriteOff(mesh, out);
            break;
          default:
            WritePly(mesh, options.colors, out);
        }
        return Status::Ok();
      },
      path);
}

}  // namespace sdcb
