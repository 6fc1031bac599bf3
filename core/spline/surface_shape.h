// The differential geometry of a parameterized surface at one point, from
// the first and second derivatives of a chart phi(u, v) there: unit normal,
// fundamental forms, Gaussian and mean curvature, principal curvatures and
// directions. One formula for the reference evaluator (SphericalSpline) and
// the fast one (PiecewiseSurface).
//
// Sign convention: H > 0 where the surface bends away from its normal, like
// a sphere of radius R with outward normal (H = 1/R, K = 1/R^2); the shape
// operator is S = -I^-1 II, whose trace is 2 H and determinant K.
#ifndef SDCB_CORE_SPLINE_SURFACE_SHAPE_H_
#define SDCB_CORE_SPLINE_SURFACE_SHAPE_H_

#include <Eigen/Core>

namespace sdcb {

struct SurfaceShape {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  // dphi/du, dphi/dv.
  Eigen::Vector3d du = Eigen::Vector3d::Zero();
  Eigen::Vector3d dv = Eigen::Vector3d::Zero();
  // (du x dv) / |du x dv|; zero where du, dv are dependent (singular).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  // I = [du.du du.dv; du.dv dv.dv] and II = [phi_uu.n phi_uv.n; phi_uv.n
  // phi_vv.n] (zero where singular).
  Eigen::Matrix2d first_form = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d second_form = Eigen::Matrix2d::Zero();
  // K = det II / det I and H = -trace(I^-1 II) / 2; NaN where singular.
  double gaussian_curvature = 0.0;
  double mean_curvature = 0.0;
};

// The shape at phi(0, 0) = position from the chart's derivatives. Only the
// normal components of the second derivatives matter (a tangential error in
// them changes nothing).
SurfaceShape ShapeFromDerivatives(const Eigen::Vector3d& position,
                                  const Eigen::Vector3d& du,
                                  const Eigen::Vector3d& dv,
                                  const Eigen::Vector3d& duu,
                                  const Eigen::Vector3d& duv,
                                  const Eigen::Vector3d& dvv);

// The eigenvalues k1 >= k2 of the shape operator (k1 k2 = K, k1 + k2 = 2 H)
// and their unit directions in R^3: tangent, orthogonal, d1 x d2 = normal.
// Along d, the normal turns as dn = k d (Rodrigues, with this sign). At an
// umbilic (k1 = k2) d1 is du's direction. NaN where the shape is singular.
struct PrincipalDirections {
  double k1 = 0.0, k2 = 0.0;
  Eigen::Vector3d d1 = Eigen::Vector3d::Zero();
  Eigen::Vector3d d2 = Eigen::Vector3d::Zero();
};
PrincipalDirections PrincipalDirectionsOf(const SurfaceShape& shape);

}  // namespace sdcb

#endif  // SDCB_CORE_SPLINE_SURFACE_SHAPE_H_
