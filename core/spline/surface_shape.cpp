#include "sdcb/core/spline/surface_shape.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

namespace sdcb {

SurfaceShape ShapeFromDerivatives(const Eigen::Vector3d& position,
                                  const Eigen::Vector3d& du,
                                  const Eigen::Vector3d& dv,
                                  const Eigen::Vector3d& duu,
                                  const Eigen::Vector3d& duv,
                                  const Eigen::Vector3d& dvv) {
  SurfaceShape out;
  out.position = position;
  out.du = du;
  out.dv = dv;
  const Eigen::Vector3d cross = du.cross(dv);
  const double area = cross.norm();
  if (!(area > 0)) {
    out.gaussian_curvature = out.mean_curvature =
        std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  out.normal = cross / area;
  const double e = du.dot(du), f = du.dot(dv), g = dv.dot(dv);
  const double l = duu.dot(out.normal), m = duv.dot(out.normal),
               n = dvv.dot(out.normal);
  out.first_form << e, f, f, g;
  out.second_form << l, m, m, n;
  const double det = e * g - f * f;
  out.gaussian_curvature = (l * n - m * m) / det;
  // The outward normal of a sphere gives l = -|du|^2 / R, so H = 1/R.
  out.mean_curvature = -(e * n - 2 * f * m + g * l) / (2 * det);
  return out;
}

PrincipalDirections PrincipalDirectionsOf(const SurfaceShape& shape) {
  PrincipalDirections out;
  if (!std::isfinite(shape.gaussian_curvature) ||
      !std::isfinite(shape.mean_curvature)) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    out.k1 = out.k2 = nan;
    out.d1 = out.d2 = Eigen::Vector3d::Constant(nan);
    return out;
  }
  // The eigenvalues of S = -I^-1 II from its entries (at an umbilic the
  // discriminant is then 0, not a rounding error that its root magnifies).
  const Eigen::Matrix2d s = -shape.first_form.inverse() * shape.second_form;
  const double half_trace = 0.5 * (s(0, 0) + s(1, 1));
  const double half_difference = 0.5 * (s(0, 0) - s(1, 1));
  const double root = std::sqrt(
      std::max(0.0, half_difference * half_difference + s(0, 1) * s(1, 0)));
  out.k1 = half_trace + root;
  out.k2 = half_trace - root;
  // An eigenvector for k1: the kernel of S - k1 (rank <= 1) is orthogonal
  // to its larger row. Below rounding, an umbilic: du's direction.
  const Eigen::Matrix2d a = s - out.k1 * Eigen::Matrix2d::Identity();
  const int row = a.row(0).squaredNorm() >= a.row(1).squaredNorm() ? 0 : 1;
  Eigen::Vector2d x(-a(row, 1), a(row, 0));
  if (!(x.norm() > 1e-12 * s.norm())) x = Eigen::Vector2d(1.0, 0.0);
  out.d1 = (x[0] * shape.du + x[1] * shape.dv).normalized();
  out.d2 = shape.normal.cross(out.d1);
  return out;
}

}  // namespace sdcb
