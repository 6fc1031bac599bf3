#include "sdcb/converters/mesh/mesh_export.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <sstream>

#include "sdcb/core/mesh/mesh_topology.h"
#include "sdcb/core/mesh/triangle_mesh.h"

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
  // A mesh OpenMesh's half-edge structure cannot hold (a non-manifold or
  // inconsistently oriented kept part) is found first, so that no face is
  // refused (OpenMesh would print that on its own error stream): the OBJ is
  // written as given; PLY and STL (one mesh of floats) get every face on
  // copies of its three vertices, as OpenMesh's readers do.
  TriangleMesh triangles;
  triangles.vertices = mesh.positions;
  triangles.faces = mesh.faces;
  const StatusOr<MeshTopologyReport> topology = AnalyzeMeshTopology(triangles);
  bool soup = !topology.ok() || topology->non_manifold_edges > 0 ||
              topology->non_manifold_vertices > 0 ||
              topology->inconsistently_oriented_edges > 0;
  for (Eigen::Index f = 0; !soup && f < mesh.faces.rows(); ++f) {
    const auto& c = mesh.faces.row(f);
    soup = c(0) == c(1) || c(1) == c(2) || c(2) == c(0);
  }
  if (soup && ext == ".obj") return EncodeObjWithDoubles(mesh);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    OmMesh::VertexHandle corners[3];
    for (int k = 0; k < 3; ++k) {
      const OmMesh::VertexHandle h = handles[mesh.faces(f, k)];
      corners[k] = h;
      if (!soup) continue;
      corners[k] = om.add_vertex(om.point(h));
      if (normals) om.set_normal(corners[k], om.normal(h));
      if (colors) om.set_color(corners[k], om.color(h));
    }
    if (!om.add_face(corners[0], corners[1], corners[2]).is_valid()) {
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
