#include "sdcb/core/param/central_projection.h"

#include <Eigen/Geometry>

namespace sdcb {

std::optional<Eigen::MatrixX3d> CentralProjection(const TriangleMesh& mesh) {
  if (mesh.vertices.rows() == 0 || mesh.faces.rows() == 0) return std::nullopt;
  const Eigen::RowVector3d centroid = mesh.vertices.colwise().mean();
  const double size =
      (mesh.vertices.colwise().maxCoeff() - mesh.vertices.colwise().minCoeff())
          .norm();
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0)).transpose();
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1)).transpose();
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2)).transpose();
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (!(n.norm() > 0)) return std::nullopt;
    if (!(n.normalized().dot(a - centroid.transpose()) > 1e-9 * size)) {
      return std::nullopt;
    }
  }
  Eigen::MatrixX3d sphere = mesh.vertices.rowwise() - centroid;
  for (Eigen::Index v = 0; v < sphere.rows(); ++v) {
    const double length = sphere.row(v).norm();
    if (!(length > 0)) return std::nullopt;
    sphere.row(v) /= length;
  }
  return sphere;
}

}  // namespace sdcb
