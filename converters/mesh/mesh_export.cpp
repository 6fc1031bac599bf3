#include "sdcb/converters/mesh/mesh_export.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <sstream>

namespace sdcb {
namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
  typedef OpenMesh::Vec3uc Color;
};
using OmMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

}  // namespace

StatusOr<std::string> EncodeSurfaceMesh(const SurfaceMesh& mesh,
                                        const std::string& extension) {
  std::string ext = extension;
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext != ".obj" && ext != ".ply" && ext != ".stl") {
    return InvalidArgumentError("unknown mesh extension '" + extension +
                                "' (use .obj, .ply or .stl)");
  }
  OmMesh om;
  const bool normals =
      mesh.normals.rows() == mesh.positions.rows() && mesh.positions.rows() > 0;
  const bool colors = ext == ".ply" &&
                      mesh.colors.rows() == mesh.positions.rows() &&
                      mesh.positions.rows() > 0;
  if (normals) om.request_vertex_normals();
  if (colors) om.request_vertex_colors();
  std::vector<OmMesh::VertexHandle> handles;
  handles.reserve(mesh.positions.rows());
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
    const auto h = om.add_vertex(OmMesh::Point(
        mesh.positions(v, 0), mesh.positions(v, 1), mesh.positions(v, 2)));
    if (normals) {
      om.set_normal(h, OmMesh::Normal(mesh.normals(v, 0), mesh.normals(v, 1),
                                      mesh.normals(v, 2)));
    }
    if (colors) {
      om.set_color(h, OmMesh::Color(mesh.colors(v, 0), mesh.colors(v, 1),
                                    mesh.colors(v, 2)));
    }
    handles.push_back(h);
  }
  // OpenMesh reports a face it refuses on its own error stream; a library
  // does not print (the refusal is handled below), so that is off meanwhile.
  OpenMesh::mostream& om_errors = omerr();
  const bool errors_shown = om_errors.is_enabled();
  om_errors.disable();
  struct Restore {
    OpenMesh::mostream& stream;
    bool shown;
    ~Restore() {
      if (shown) stream.enable();
    }
  } restore{om_errors, errors_shown};
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    if (om.add_face(handles[mesh.faces(f, 0)], handles[mesh.faces(f, 1)],
                    handles[mesh.faces(f, 2)])
            .is_valid()) {
      continue;
    }
    // A face that is not manifold: the OBJ is written as given; PLY and STL
    // (one mesh of floats) get the face on copies of its three vertices, as
    // OpenMesh's readers do.
    if (ext == ".obj") return EncodeObjWithDoubles(mesh);
    OmMesh::VertexHandle copies[3];
    for (int k = 0; k < 3; ++k) {
      const OmMesh::VertexHandle h = handles[mesh.faces(f, k)];
      copies[k] = om.add_vertex(om.point(h));
      if (normals) om.set_normal(copies[k], om.normal(h));
      if (colors) om.set_color(copies[k], om.color(h));
    }
    if (!om.add_face(copies[0], copies[1], copies[2]).is_valid()) {
      return InvalidInputError("face " + std::to_string(f) +
                               " cannot be written");
    }
  }
  OpenMesh::IO::Options options;
  if (ext != ".obj") options += OpenMesh::IO::Options::Binary;
  if (normals && ext != ".stl") options += OpenMesh::IO::Options::VertexNormal;
  if (colors) options += OpenMesh::IO::Options::VertexColor;
  std::ostringstream out(std::ios::binary);
  bool ok = false;
  try {
    ok = OpenMesh::IO::write_mesh(om, out, ext, options, 17);
  } catch (const std::exception&) {
    ok = false;
  }
  if (!ok) return IoError("OpenMesh could not write the mesh");
  return std::move(out).str();
}

std::string EncodeObjWithDoubles(const SurfaceMesh& mesh) {
  const bool normals =
      mesh.normals.rows() == mesh.positions.rows() && mesh.positions.rows() > 0;
  std::string out = "# " + std::to_string(mesh.positions.rows()) +
                    " vertices, " + std::to_string(mesh.faces.rows()) +
                    " faces\n";
  char line[128];
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
    std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n",
                  mesh.positions(v, 0), mesh.positions(v, 1),
                  mesh.positions(v, 2));
    out += line;
    if (!normals) continue;
    std::snprintf(line, sizeof line, "vn %.17g %.17g %.17g\n",
                  mesh.normals(v, 0), mesh.normals(v, 1), mesh.normals(v, 2));
    out += line;
  }
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    out += "f";
    for (int k = 0; k < 3; ++k) {
      const std::string i = std::to_string(mesh.faces(f, k) + 1);
      out += " " + i + (normals ? "//" + i : "");
    }
    out += "\n";
  }
  return out;
}

}  // namespace sdcb
