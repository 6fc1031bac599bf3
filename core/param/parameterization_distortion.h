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
#include <limits>
#include <vector>

#include "sdcb/core/common/status.h"
#include "sdcb/core/mesh/triangle_mesh.h"

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
// 1e-9 (Det3 does not). A value, not a decision: decisions use Det3Sign.
double SmallTriangleDet3(const Eigen::Vector3d& s0, const Eigen::Vector3d& s1,
                         const Eigen::Vector3d& s2);

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
// a triangle that is not positively oriented). When `grad_s0`
// is not null it receives the gradient in R^3 with respect to s0 (the
// caller projects it onto the sphere's tangent plane).
double TriangleEnergy(const MeshTriangleShape& shape, const Eigen::Vector3d& s0,
                      const Eigen::Vector3d& s1, const Eigen::Vector3d& s2,
                      double lambda, Eigen::Vector3d* grad_s0 = nullptr);

// Area factor that scales `mesh` to total area 4*pi (multiply areas by it).
// kInvalidInput for a mesh of zero or non-finite total area.
StatusOr<double> AreaScaleToUnitSphere(const TriangleMesh& mesh);

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
