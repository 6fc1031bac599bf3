#include "sdcb/core/param/central_projection.h"

#include <Eigen/Geometry>

namespace sdcb {

std::optional<Eigen::MatrixX3d> CentralProjection(const TriangleMesh& mesh) {
  if (mesh.vertices.rows() == 0 || mesh.faces.rows() == 0) return std::nullopt;
  const Eigen::RowVector3d centroid = mesh.vertices.colwise().mean();
  const double size =
      (mesh.vertices.colwise().maxCoeff() - mesh.vertices.colwise().minCoeff())
          .norm();
  // +1 when every face sees the centroid from inside with its outward
  // normal, -1 when every face does with its normal pointing in.
  int side = 0;
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0)).transpose();
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1)).transpose();
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2)).transpose();
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (!(n.norm() > 0)) return std::nullopt;
    const double height = n.normalized().dot(a - centroid.transpose());
    const int face_side =
        height > 1e-9 * size ? 1 : (height < -1e-9 * size ? -1 : 0);
    if (face_side == 0 || (side != 0 && face_side != side)) return std::nullopt;
    side = face_side;
  }
  Eigen::MatrixX3d sphere = mesh.vertices.rowwise() - centroid;
  for (Eigen::Index v = 0; v < sphere.rows(); ++v) {
    const double length = sphere.row(v).norm();
    if (!(length > 0)) return std::nullopt;
    sphere.row(v) /= length;
  }
  // Inward faces: mirrored, so that the sphere triangles keep the faces'
  // order counter-clockwise, as the parameterization's do.
  if (side < 0) sphere.col(0) = -sphere.col(0);
  return sphere;
}

}  // namespace sdcb
