// Distortion of a spherical parameterization (paper Sec. 4.3, eqs. 8-12):
// the per-triangle angle and area distortions, the energy the
// parameterization minimizes, and the Table-1 summary metrics.
//
// Conventions used everywhere in sdcb (one place for each formula):
// - area(T_S2) in eqs. (10) and (11) is the area of the spherical
//   (geodesic) triangle, its solid angle; the edge lengths |e_i| of eq. (10)
//   are chord lengths. Reasons: the spherical areas of a bijection sum to
//   exactly 4*pi, the total the mesh is scaled to; and the area goes to 0
//   as a triangle approaches a fold (its three points on one great circle),
//   a barrier that keeps the optimizer away from folds, which the chord
//   triangle's area does not give (it stays positive there).
// - For two flat triangles the eq.-10 form is exactly sigma1/sigma2 +
//   sigma2/sigma1 of the affine map between them (AngleDistortionFormula
//   with the flat area). On the sphere the spherical and chord areas differ
//   by a factor 1 + O(h^2) (h: edge length), so E_angle can differ from
//   sigma1/sigma2 + sigma2/sigma1 (and even be below 2) by O(h^2): an
//   icosphere mapped to itself gives E_angle = 2 - O(h^2) and E_area =
//   2 + O(h^4).
#ifndef SDCB_CORE_PARAM_PARAMETERIZATION_DISTORTION_H_
#define SDCB_CORE_PARAM_PARAMETERIZATION_DISTORTION_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"
#include "sdcb/core/sphere/sphere_geometry.h"

namespace sdcb {

// What eqs. 10-12 need of a mesh triangle: the cotangents of its angles
// (cot[i] at corner i, opposite the edge from corner i+1 to corner i+2) and
// its area after the mesh was scaled to total area 4*pi.
struct MeshTriangleShape {
  Eigen::Vector3d cot = Eigen::Vector3d::Zero();
  double area = 0.0;
};

// Shape of the mesh triangle (m0, m1, m2) scaled by `area_scale` (areas are
// multiplied by it; cotangents do not change). A degenerate triangle gives
// infinite cotangents.
MeshTriangleShape ComputeMeshTriangleShape(const Eigen::Vector3d& m0,
                                           const Eigen::Vector3d& m1,
                                           const Eigen::Vector3d& m2,
                                           double area_scale);

// The same shape with its corners renumbered so that corner `first` becomes
// corner 0 (a rotation, orientation kept).
MeshTriangleShape RotateShape(const MeshTriangleShape& shape, int first);

// det[s0 s1 s2] as s0 . ((s1 - s0) x (s2 - s0)): the same value, but with a
// rounding error relative to the triangle's size instead of about 1e-16
// absolute, so it keeps its sign and digits for triangles with edges of
// 1e-9 (Det3 does not). A value, not a decision: decisions use Det3Sign or
// SmallTriangleDet3Sign. (Inline: the optimizer's inner loop calls it.)
inline double SmallTriangleDet3(const Eigen::Vector3d& s0,
                                const Eigen::Vector3d& s1,
                                const Eigen::Vector3d& s2) {
  // det[s0 s1 s2] = det[s0, s1 - s0, s2 - s0]; the differences of nearby
  // points are (almost) exact, s1 x s2 would cancel.
  return s0.dot((s1 - s0).cross(s2 - s0));
}

// The exact sign of det[s0 s1 s2] (as Det3Sign), and SmallTriangleDet3 in
// *det. A filter: the floating-point value decides when it exceeds a bound
// of its rounding error, else the exact predicate runs. The bound: with
// d = s1 - s0 and e = s2 - s0 rounded (relative error eps = 2^-53 per
// coordinate) and the products and sums of s0 . (d x e) rounded (at most 5
// roundings per term), the computed value is within (7 eps + O(eps^2)) P
// of the exact det, P = sum_i |s0_i| (|d_j e_k| + |d_k e_j|); the filter
// uses 1e-15 P (> 9 eps P). Nearly all calls of the optimizer decide in
// the filter (a triangle with edges of 1e-3 has det ~ 1e-6, the bound is
// ~ 1e-21), so the cost is that of the floating-point determinant.
inline int SmallTriangleDet3Sign(const Eigen::Vector3d& s0,
                                 const Eigen::Vector3d& s1,
                                 const Eigen::Vector3d& s2, double* det) {
  const Eigen::Vector3d d = s1 - s0, e = s2 - s0;
  const double c0 = d.y() * e.z() - d.z() * e.y();
  const double c1 = d.z() * e.x() - d.x() * e.z();
  const double c2 = d.x() * e.y() - d.y() * e.x();
  *det = s0.x() * c0 + s0.y() * c1 + s0.z() * c2;
  const double permanent =
      std::abs(s0.x()) * (std::abs(d.y() * e.z()) + std::abs(d.z() * e.y())) +
      std::abs(s0.y()) * (std::abs(d.z() * e.x()) + std::abs(d.x() * e.z())) +
      std::abs(s0.z()) * (std::abs(d.x() * e.y()) + std::abs(d.y() * e.x()));
  const double bound = 1e-15 * permanent;
  if (*det > bound) return 1;
  if (*det < -bound) return -1;
  return Det3Sign(s0, s1, s2);
}

// 2 atan2(det, denominator), the spherical triangle's area from the two
// parts of Van Oosterom and Strackee's formula (see SphericalTriangleArea).
// For |det| <= denominator / 8 (every triangle below ~0.25 steradians) by
// the odd series of atan(x), x = det / denominator, up to x^17 (the first
// omitted term is below 3e-18 of the sum): several times cheaper than
// atan2, and as accurate.
inline double SphericalAreaFromParts(double det, double denominator) {
  if (denominator > 0.0 && 8.0 * std::abs(det) <= denominator) {
    const double x = det / denominator;
    const double y = x * x;
    const double series =
        1.0 -
        y * (1.0 / 3 -
             y * (1.0 / 5 -
                  y * (1.0 / 7 -
                       y * (1.0 / 9 -
                            y * (1.0 / 11 -
                                 y * (1.0 / 13 -
                                      y * (1.0 / 15 - y * (1.0 / 17))))))));
    return 2.0 * x * series;
  }
  return 2.0 * std::atan2(det, denominator);
}

// Signed area of the spherical triangle (s0, s1, s2) (unit vectors): its
// solid angle, in (-2*pi, 2*pi), positive when det[s0 s1 s2] > 0.
double SphericalTriangleArea(const Eigen::Vector3d& s0,
                             const Eigen::Vector3d& s1,
                             const Eigen::Vector3d& s2);

// Eq. (10) from its parts: sum_i cot_i |e_i|^2 and area(T_S2). Infinite
// for area <= 0. (Inline: the optimizer's inner loop calls it.)
inline double AngleDistortionFormula(double cot_weighted_edges,
                                     double sphere_area) {
  if (!(sphere_area > 0.0)) return std::numeric_limits<double>::infinity();
  return cot_weighted_edges / (2.0 * sphere_area);
}

// Eq. (11) from the two areas. Infinite when either is <= 0.
inline double AreaDistortionFormula(double mesh_area, double sphere_area) {
  if (!(sphere_area > 0.0) || !(mesh_area > 0.0)) {
    return std::numeric_limits<double>::infinity();
  }
  return sphere_area / mesh_area + mesh_area / sphere_area;
}

// Eq. (10): E_angle = (sum_i cot_i |e_i|^2) / (2 area(T_S2)) with e_i the
// chord opposite corner i. Infinite unless T_S2 is positively oriented.
double AngleDistortion(const MeshTriangleShape& shape,
                       const Eigen::Vector3d& s0, const Eigen::Vector3d& s1,
                       const Eigen::Vector3d& s2);

// Eq. (11): E_area = area(T_S2)/area(T_M) + area(T_M)/area(T_S2), with the
// spherical triangle's area.
double AreaDistortion(const MeshTriangleShape& shape, const Eigen::Vector3d& s0,
                      const Eigen::Vector3d& s1, const Eigen::Vector3d& s2);

// One term of eq. (12): area(T_M) * E_angle * E_area^lambda (infinite for
// a triangle that is not positively oriented), for `det` =
// SmallTriangleDet3(s0, s1, s2) computed by the caller. When `grad_s0` is
// not null it receives the gradient in R^3 with respect to s0 (the caller
// projects it onto the sphere's tangent plane). Inline: the optimizer's
// inner loop calls it.
inline double TriangleEnergyWithDet(const MeshTriangleShape& shape,
                                    const Eigen::Vector3d& s0,
                                    const Eigen::Vector3d& s1,
                                    const Eigen::Vector3d& s2, double det,
                                    double lambda,
                                    Eigen::Vector3d* grad_s0 = nullptr) {
  const double denominator = 1.0 + s0.dot(s1) + s1.dot(s2) + s2.dot(s0);
  const double a = SphericalAreaFromParts(det, denominator);
  const double am = shape.area;
  const Eigen::Vector3d d01 = s1 - s0, d02 = s2 - s0;
  // sum_i cot_i |e_i|^2, the numerator of eq. (10).
  const double n = shape.cot[0] * (s2 - s1).squaredNorm() +
                   shape.cot[1] * d02.squaredNorm() +
                   shape.cot[2] * d01.squaredNorm();
  if (!(a > 0.0) || !(am > 0.0) || !std::isfinite(n)) {
    if (grad_s0 != nullptr) grad_s0->setZero();
    return std::numeric_limits<double>::infinity();
  }
  // am E_angle E_area^lambda with E_angle = n / (2a) and E_area = r + 1/r,
  // r = a / am; for lambda = 1 it is n / 2 (1 + (am / a)^2).
  const double inv_a = 1.0 / a;
  const double e_angle = 0.5 * n * inv_a;
  const double e_area = a / am + am * inv_a;
  const double area_pow = lambda == 1.0 ? e_area : std::pow(e_area, lambda);
  const double energy = am * e_angle * area_pow;
  if (grad_s0 != nullptr) {
    // d area / d s0 = 2 (D grad(det) - det grad(D)) / (det^2 + D^2).
    const Eigen::Vector3d d_a =
        (2.0 / (det * det + denominator * denominator)) *
        (denominator * s1.cross(s2) - det * (s1 + s2));
    const Eigen::Vector3d d_n =
        -2.0 * (shape.cot[1] * d02 + shape.cot[2] * d01);
    const Eigen::Vector3d d_angle = 0.5 * inv_a * (d_n - n * inv_a * d_a);
    const Eigen::Vector3d d_area = (1.0 / am - am * inv_a * inv_a) * d_a;
    *grad_s0 = am * (area_pow * d_angle +
                     e_angle * lambda * (area_pow / e_area) * d_area);
  }
  return energy;
}

// One term of eq. (12), TriangleEnergyWithDet with the determinant computed
// here.
inline double TriangleEnergy(const MeshTriangleShape& shape,
                             const Eigen::Vector3d& s0,
                             const Eigen::Vector3d& s1,
                             const Eigen::Vector3d& s2, double lambda,
                             Eigen::Vector3d* grad_s0 = nullptr) {
  return TriangleEnergyWithDet(shape, s0, s1, s2, SmallTriangleDet3(s0, s1, s2),
                               lambda, grad_s0);
}

// Area factor that scales `mesh` to total area 4*pi (multiply areas by it).
// kInvalidInput for a mesh of zero or non-finite total area.
StatusOr<double> AreaScaleToUnitSphere(const TriangleMesh& mesh);

// The parameterization's area ratio at every vertex: the mesh area of the
// vertex's triangles over the spherical area of their images, with the mesh
// scaled to total area 4*pi (AreaScaleToUnitSphere), so 1 where the map
// keeps area; above 1 where it compresses the surface (thin parts, sharp
// features). `sphere`: #V by 3 unit vectors (a bijective map, either
// orientation). A vertex without triangles, or whose images have no area,
// gets 1. kInvalidArgument when the sizes do not match; kInvalidInput for a
// mesh without area.
StatusOr<Eigen::VectorXd> VertexAreaRatio(const TriangleMesh& mesh,
                                          const Eigen::MatrixX3d& sphere);

// Paper Table 1, for a mesh and a position on S^2 for each of its vertices.
struct ParameterizationDistortion {
  double angle_distortion_max = 0.0;
  double angle_distortion_avg = 0.0;  // weighted by mesh-triangle area
  double area_distortion_max = 0.0;
  double area_distortion_avg = 0.0;  // weighted by mesh-triangle area
  // Faces whose sphere triangle is not positively oriented (exact sign of
  // det[s0 s1 s2] <= 0), i.e. folded or degenerate.
  int flipped_triangles = 0;
  // Per face: E_angle and E_area (#F entries each, in face order).
  std::vector<double> face_angle_distortion;
  std::vector<double> face_area_distortion;
  // Per face: mesh-triangle area after scaling the mesh to area 4*pi.
  std::vector<double> face_mesh_area;
};

// Measures `sphere` (#V by 3, unit vectors, row i for mesh vertex i) as a map
// of `mesh`. Flipped faces count in `flipped_triangles` but not in the
// max/avg values. kInvalidArgument when the sizes do not match.
StatusOr<ParameterizationDistortion> MeasureParameterizationDistortion(
    const TriangleMesh& mesh, const Eigen::MatrixX3d& sphere);

}  // namespace sdcb

#endif  // SDCB_CORE_PARAM_PARAMETERIZATION_DISTORTION_H_
