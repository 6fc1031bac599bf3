#include "sdcb/core/sphere/sphere_geometry.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/Geometry>
#include <cmath>

namespace sdcb {

Eigen::Index FirstNonUnitRow(const Eigen::MatrixX3d& points) {
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const double n = points.row(i).norm();
    if (!std::isfinite(n) || std::abs(n - 1.0) > kUnitVectorTolerance) {
      return i;
    }
  }
  return -1;
}

bool AllUnitRows(const Eigen::MatrixX3d& points) {
  return FirstNonUnitRow(points) < 0;
}

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

Kernel::Point_3 ToPoint(const Eigen::Vector3d& v) {
  return Kernel::Point_3(v.x(), v.y(), v.z());
}

int SignOf(CGAL::Orientation o) {
  return o == CGAL::POSITIVE ? 1 : (o == CGAL::NEGATIVE ? -1 : 0);
}

}  // namespace

int Orient3dSign(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                 const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  // CGAL::orientation(p, q, r, s) is the sign of det[q-p, r-p, s-p].
  return SignOf(
      CGAL::orientation(ToPoint(a), ToPoint(b), ToPoint(c), ToPoint(d)));
}

int Det3Sign(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
             const Eigen::Vector3d& c) {
  return Orient3dSign(Eigen::Vector3d::Zero(), a, b, c);
}

int CapSide(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
            const Eigen::Vector3d& c, const Eigen::Vector3d& q) {
  const int origin_side = Orient3dSign(a, b, c, Eigen::Vector3d::Zero());
  if (origin_side == 0) return 0;
  const int q_side = Orient3dSign(a, b, c, q);
  return -q_side * origin_side;
}

bool InOpenHemisphere(const Eigen::MatrixX3d& points) {
  const int m = static_cast<int>(points.rows());
  auto at = [&](int i) -> Eigen::Vector3d { return points.row(i).transpose(); };
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  // Filter: if the sum n of the points has n . t clearly positive for every
  // point t (beyond the rounding of the dot products, < 1e-15 |n| |t|),
  // the open hemisphere around n holds them all.
  const Eigen::Vector3d n = points.colwise().sum().transpose();
  bool clearly_inside = true;
  for (int i = 0; i < m && clearly_inside; ++i) {
    clearly_inside = n.dot(at(i)) > 1e-12 * n.norm() * at(i).norm();
  }
  if (clearly_inside) return true;
  // Segments: the origin is on [a, b] iff b is a negative multiple of a,
  // i.e. a x b = 0 (exactly: every 2 x 2 minor vanishes) and a . b < 0.
  for (int a = 0; a < m; ++a)
    for (int b = a + 1; b < m; ++b) {
      bool parallel = true;
      for (int axis = 0; axis < 3 && parallel; ++axis) {
        parallel = Det3Sign(at(a), at(b), Eigen::Vector3d::Unit(axis)) == 0;
      }
      if (parallel && at(a).dot(at(b)) < 0) return false;
    }
  for (int a = 0; a < m; ++a)
    for (int b = a + 1; b < m; ++b)
      for (int c = b + 1; c < m; ++c) {
        if (Det3Sign(at(a), at(b), at(c)) != 0) continue;
        // A triangle in a plane through the origin: orient its edges as
        // seen from a coordinate axis e off that plane (det(u, v, e) has
        // the sign of the in-plane cross product u x v, up to one fixed
        // factor); the origin is in the closed triangle iff no two edges
        // turn opposite ways.
        int axis = 0;
        while (axis < 3 &&
               Det3Sign(at(a), at(b), Eigen::Vector3d::Unit(axis)) == 0 &&
               Det3Sign(at(b), at(c), Eigen::Vector3d::Unit(axis)) == 0) {
          ++axis;
        }
        if (axis == 3) continue;  // all three parallel: segments decide
        const Eigen::Vector3d e = Eigen::Vector3d::Unit(axis);
        const int o1 = Det3Sign(at(a), at(b), e);
        const int o2 = Det3Sign(at(b), at(c), e);
        const int o3 = Det3Sign(at(c), at(a), e);
        if ((o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0))
          return false;
      }
  for (int a = 0; a < m; ++a)
    for (int b = a + 1; b < m; ++b)
      for (int c = b + 1; c < m; ++c)
        for (int d = c + 1; d < m; ++d) {
          const int s = Orient3dSign(at(a), at(b), at(c), at(d));
          if (s == 0) continue;  // flat: the triangles decide
          // The origin is in the closed tetrahedron iff replacing any corner
          // by it never flips the orientation.
          if (Orient3dSign(origin, at(b), at(c), at(d)) * s >= 0 &&
              Orient3dSign(at(a), origin, at(c), at(d)) * s >= 0 &&
              Orient3dSign(at(a), at(b), origin, at(d)) * s >= 0 &&
              Orient3dSign(at(a), at(b), at(c), origin) * s >= 0) {
            return false;
          }
        }
  return true;
}

void TangentFrame(const Eigen::Vector3d& p, Eigen::Vector3d* e_u,
                  Eigen::Vector3d* e_v) {
  // Cross with the coordinate axis least aligned with p.
  int axis = 0;
  p.cwiseAbs().minCoeff(&axis);
  *e_u = Eigen::Vector3d::Unit(axis).cross(p).normalized();
  *e_v = p.cross(*e_u);
}

}  // namespace sdcb
