// Spherical barycentric coordinates (paper eq. 2), the one place they are
// computed. For knots t0, t1, t2 (linearly independent) and p in R^3:
//   b0 = det(p,t1,t2)/D, b1 = det(t0,p,t2)/D, b2 = det(t0,t1,p)/D,
// D = det(t0,t1,t2). They are linear in p, b = G p, with the rows of G the
// constant gradients (t1 x t2)/D, (t2 x t0)/D, (t0 x t1)/D. On S^2,
// b0 + b1 + b2 >= 1 inside the triangle (not a partition of unity).
#ifndef SDCB_CORE_SPHERE_SPHERICAL_BARYCENTRIC_H_
#define SDCB_CORE_SPHERE_SPHERICAL_BARYCENTRIC_H_

#include <Eigen/Core>

namespace sdcb {

// The 3 by 3 matrix G with b(p) = G p; row j is the gradient of b_j.
// Requires det(t0, t1, t2) != 0 (else the result is not finite).
Eigen::Matrix3d SphericalBarycentricMatrix(const Eigen::Vector3d& t0,
                                           const Eigen::Vector3d& t1,
                                           const Eigen::Vector3d& t2);

// (b0, b1, b2) of p with respect to (t0, t1, t2), eq. 2.
Eigen::Vector3d SphericalBarycentric(const Eigen::Vector3d& p,
                                     const Eigen::Vector3d& t0,
                                     const Eigen::Vector3d& t1,
                                     const Eigen::Vector3d& t2);

}  // namespace sdcb

#endif  // SDCB_CORE_SPHERE_SPHERICAL_BARYCENTRIC_H_
