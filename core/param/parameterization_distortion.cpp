#include "sdcb/core/param/parameterization_distortion.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "sdcb/core/common/constants.h"
#include "sdcb/core/sphere/sphere_geometry.h"

namespace sdcb {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Area of the flat triangle (a, b, c) and its unit normal.
double FlatArea(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                const Eigen::Vector3d& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

// cot of the angle between u and v.
double Cot(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  const double sin_norm = u.cross(v).norm();
  if (sin_norm == 0.0) return kInf;
  return u.dot(v) / sin_norm;
}

// sum_i cot_i |e_i|^2, the numerator of eq. (10).
double CotWeightedEdges(const MeshTriangleShape& shape,
                        const Eigen::Vector3d& s0, const Eigen::Vector3d& s1,
                        const Eigen::Vector3d& s2) {
  return shape.cot[0] * (s2 - s1).squaredNorm() +
         shape.cot[1] * (s0 - s2).squaredNorm() +
         shape.cot[2] * (s1 - s0).squaredNorm();
}

}  // namespace

MeshTriangleShape ComputeMeshTriangleShape(const Eigen::Vector3d& m0,
                                           const Eigen::Vector3d& m1,
                                           const Eigen::Vector3d& m2,
                                           double area_scale) {
  MeshTriangleShape shape;
  shape.cot[0] = Cot(m1 - m0, m2 - m0);
  shape.cot[1] = Cot(m2 - m1, m0 - m1);
  shape.cot[2] = Cot(m0 - m2, m1 - m2);
  shape.area = FlatArea(m0, m1, m2) * area_scale;
  return shape;
}

MeshTriangleShape RotateShape(const MeshTriangleShape& shape, int first) {
  MeshTriangleShape rotated = shape;
  for (int i = 0; i < 3; ++i) rotated.cot[i] = shape.cot[(i + first) % 3];
  return rotated;
}

double SphericalTriangleArea(const Eigen::Vector3d& s0,
                             const Eigen::Vector3d& s1,
                             const Eigen::Vector3d& s2) {
  // Van Oosterom and Strackee: tan(area / 2) = det / (1 + s0.s1 + s1.s2 +
  // s2.s0).
  return 2.0 * std::atan2(SmallTriangleDet3(s0, s1, s2),
                          1.0 + s0.dot(s1) + s1.dot(s2) + s2.dot(s0));
}

double AngleDistortion(const MeshTriangleShape& shape,
                       const Eigen::Vector3d& s0, const Eigen::Vector3d& s1,
                       const Eigen::Vector3d& s2) {
  return AngleDistortionFormula(CotWeightedEdges(shape, s0, s1, s2),
                                SphericalTriangleArea(s0, s1, s2));
}

double AreaDistortion(const MeshTriangleShape& shape, const Eigen::Vector3d& s0,
                      const Eigen::Vector3d& s1, const Eigen::Vector3d& s2) {
  return AreaDistortionFormula(shape.area, SphericalTriangleArea(s0, s1, s2));
}

StatusOr<double> AreaScaleToUnitSphere(const TriangleMesh& mesh) {
  double total = 0.0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    total += FlatArea(mesh.vertices.row(mesh.faces(f, 0)).transpose(),
                      mesh.vertices.row(mesh.faces(f, 1)).transpose(),
                      mesh.vertices.row(mesh.faces(f, 2)).transpose());
  }
  if (!(total > 0.0) || !std::isfinite(total)) {
    return InvalidInputError("mesh has zero or non-finite total area");
  }
  return 4.0 * kPi / total;
}

StatusOr<ParameterizationDistortion> MeasureParameterizationDistortion(
    const TriangleMesh& mesh, const Eigen::MatrixX3d& sphere) {
  if (sphere.rows() != mesh.num_vertices()) {
    return InvalidArgumentError(
        "parameterization has " + std::to_string(sphere.rows()) +
        " points for a mesh of " + std::to_string(mesh.num_vertices()) +
        " vertices");
  }
  SDCB_ASSIGN_OR_RETURN(const double scale, AreaScaleToUnitSphere(mesh));
  ParameterizationDistortion d;
  d.face_angle_distortion.assign(mesh.num_faces(), kInf);
  d.face_area_distortion.assign(mesh.num_faces(), kInf);
  d.face_mesh_area.assign(mesh.num_faces(), 0.0);
  double weight = 0.0, angle_sum = 0.0, area_sum = 0.0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    Eigen::Vector3d m[3], s[3];
    for (int i = 0; i < 3; ++i) {
      m[i] = mesh.vertices.row(mesh.faces(f, i)).transpose();
      s[i] = sphere.row(mesh.faces(f, i)).transpose();
    }
    const MeshTriangleShape shape =
        ComputeMeshTriangleShape(m[0], m[1], m[2], scale);
    d.face_mesh_area[f] = shape.area;
    if (Det3Sign(s[0], s[1], s[2]) <= 0) {
      ++d.flipped_triangles;
      continue;
    }
    const double e_angle = AngleDistortion(shape, s[0], s[1], s[2]);
    const double e_area = AreaDistortion(shape, s[0], s[1], s[2]);
    d.face_angle_distortion[f] = e_angle;
    d.face_area_distortion[f] = e_area;
    d.angle_distortion_max = std::max(d.angle_distortion_max, e_angle);
    d.area_distortion_max = std::max(d.area_distortion_max, e_area);
    weight += shape.area;
    angle_sum += shape.area * e_angle;
    area_sum += shape.area * e_area;
  }
  if (weight > 0.0) {
    d.angle_distortion_avg = angle_sum / weight;
    d.area_distortion_avg = area_sum / weight;
  }
  return d;
}

StatusOr<Eigen::VectorXd> VertexAreaRatio(const TriangleMesh& mesh,
                                          const Eigen::MatrixX3d& sphere) {
  if (sphere.rows() != mesh.vertices.rows()) {
    return InvalidArgumentError(
        "the sphere points must be one per mesh vertex");
  }
  SDCB_ASSIGN_OR_RETURN(const double scale, AreaScaleToUnitSphere(mesh));
  Eigen::VectorXd mesh_area = Eigen::VectorXd::Zero(sphere.rows());
  Eigen::VectorXd sphere_area = Eigen::VectorXd::Zero(sphere.rows());
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3i v = mesh.faces.row(f).transpose();
    const Eigen::Vector3d m0 = mesh.vertices.row(v[0]);
    const Eigen::Vector3d m1 = mesh.vertices.row(v[1]);
    const Eigen::Vector3d m2 = mesh.vertices.row(v[2]);
    const double a = 0.5 * scale * (m1 - m0).cross(m2 - m0).norm();
    const double s = std::abs(SphericalTriangleArea(
        sphere.row(v[0]).transpose(), sphere.row(v[1]).transpose(),
        sphere.row(v[2]).transpose()));
    for (int k = 0; k < 3; ++k) {
      mesh_area[v[k]] += a;
      sphere_area[v[k]] += s;
    }
  }
  Eigen::VectorXd ratio = Eigen::VectorXd::Ones(sphere.rows());
  for (Eigen::Index i = 0; i < ratio.size(); ++i) {
    if (sphere_area[i] > 0 && mesh_area[i] > 0) {
      ratio[i] = mesh_area[i] / sphere_area[i];
    }
  }
  return ratio;
}

}  // namespace sdcb
