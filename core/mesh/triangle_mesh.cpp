#include "sdcb/core/mesh/triangle_mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace sdcb {

Status CheckFaceIndices(const TriangleMesh& mesh) {
  const int nv = mesh.num_vertices();
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces(f, k);
      if (v < 0 || v >= nv) {
        return InvalidInputError("face " + std::to_string(f) +
                                 " refers to vertex " + std::to_string(v) +
                                 ", but there are only " + std::to_string(nv) +
                                 " vertices");
      }
    }
  }
  return Status::Ok();
}

Eigen::VectorXd VertexAreas(const TriangleMesh& mesh) {
  Eigen::VectorXd area = Eigen::VectorXd::Zero(mesh.vertices.rows());
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    const double t = 0.5 * (b - a).cross(c - a).norm();
    for (int k = 0; k < 3; ++k) area[mesh.faces(f, k)] += t / 3;
  }
  return area;
}

Eigen::MatrixX3d VertexNormals(const TriangleMesh& mesh) {
  Eigen::MatrixX3d normal = Eigen::MatrixX3d::Zero(mesh.vertices.rows(), 3);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    const Eigen::RowVector3d n = 0.5 * (b - a).cross(c - a).transpose();
    for (int k = 0; k < 3; ++k) normal.row(mesh.faces(f, k)) += n;
  }
  for (Eigen::Index v = 0; v < normal.rows(); ++v) {
    const double length = normal.row(v).norm();
    if (length > 0) normal.row(v) /= length;
  }
  return normal;
}

TriangleMesh MidpointSubdivided(const TriangleMesh& mesh, int levels) {
  TriangleMesh out = mesh;
  for (int level = 0; level < levels; ++level) {
    const Eigen::Index nv = out.vertices.rows(), nf = out.faces.rows();
    // A closed mesh has 3F/2 edges; an open one at most 3F.
    std::vector<Eigen::RowVector3d> added;
    added.reserve(static_cast<size_t>(3 * nf / 2 + 1));
    std::unordered_map<uint64_t, int> midpoint;
    midpoint.reserve(static_cast<size_t>(3 * nf));
    auto middle = [&](int a, int b) {
      const uint64_t key = (static_cast<uint64_t>(std::min(a, b)) << 32) |
                           static_cast<uint32_t>(std::max(a, b));
      const auto [it, inserted] =
          midpoint.emplace(key, static_cast<int>(nv + added.size()));
      if (inserted) {
        added.push_back(0.5 * (out.vertices.row(a) + out.vertices.row(b)));
      }
      return it->second;
    };
    Eigen::MatrixX3i faces(4 * nf, 3);
    for (Eigen::Index f = 0; f < nf; ++f) {
      const int a = out.faces(f, 0), b = out.faces(f, 1), c = out.faces(f, 2);
      const int ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
      faces.row(4 * f) << a, ab, ca;
      faces.row(4 * f + 1) << ab, b, bc;
      faces.row(4 * f + 2) << ca, bc, c;
      faces.row(4 * f + 3) << ab, bc, ca;
    }
    Eigen::MatrixX3d vertices(nv + static_cast<Eigen::Index>(added.size()), 3);
    vertices.topRows(nv) = out.vertices;
    for (size_t i = 0; i < added.size(); ++i) {
      vertices.row(nv + static_cast<Eigen::Index>(i)) = added[i];
    }
    out.vertices = std::move(vertices);
    out.faces = std::move(faces);
  }
  return out;
}

}  // namespace sdcb
