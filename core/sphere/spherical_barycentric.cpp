#include "sdcb/core/sphere/spherical_barycentric.h"

#include <Eigen/Geometry>

#include "sdcb/core/sphere/sphere_geometry.h"

namespace sdcb {

Eigen::Matrix3d SphericalBarycentricMatrix(const Eigen::Vector3d& t0,
                                           const Eigen::Vector3d& t1,
                                           const Eigen::Vector3d& t2) {
  // det(p,t1,t2) = p . (t1 x t2), and cyclically for the other two.
  const double inv = 1.0 / Det3(t0, t1, t2);
  Eigen::Matrix3d g;
  g.row(0) = t1.cross(t2).transpose() * inv;
  g.row(1) = t2.cross(t0).transpose() * inv;
  g.row(2) = t0.cross(t1).transpose() * inv;
  return g;
}

Eigen::Vector3d SphericalBarycentric(const Eigen::Vector3d& p,
                                     const Eigen::Vector3d& t0,
                                     const Eigen::Vector3d& t1,
                                     const Eigen::Vector3d& t2) {
  return SphericalBarycentricMatrix(t0, t1, t2) * p;
}

}  // namespace sdcb
