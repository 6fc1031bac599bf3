#include "sdcb/core/mesh/triangle_mesh.h"

#include <Eigen/Geometry>
#include <string>

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

}  // namespace sdcb
