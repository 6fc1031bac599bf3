#include "core/sphere_geometry.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace sdcb {
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
  return SignOf(CGAL::orientation(ToPoint(a), ToPoint(b), ToPoint(c), ToPoint(d)));
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

}  // namespace sdcb
