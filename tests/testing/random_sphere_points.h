// Deterministic point sets for the basis tests and benchmarks.
#ifndef SDCB_TESTS_TESTING_RANDOM_SPHERE_POINTS_H_
#define SDCB_TESTS_TESTING_RANDOM_SPHERE_POINTS_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "sdcb/core/common/constants.h"

namespace sdcb {
namespace testing {

// `n` uniform random unit vectors (rows), from `seed`.
inline Eigen::MatrixX3d RandomUnitVectors(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::MatrixX3d out(n, 3);
  for (int i = 0; i < n; ++i) {
    out.row(i) =
        Eigen::RowVector3d(normal(rng), normal(rng), normal(rng)).normalized();
  }
  return out;
}

// Quasi-uniform knots, close to a uniform spherical CVT: a Fibonacci spiral
// with a deterministic jitter of `jitter` times the mean spacing (general
// position).
inline Eigen::MatrixX3d FibonacciPoints(int n, unsigned seed,
                                        double jitter = 0.05) {
  const Eigen::MatrixX3d noise = RandomUnitVectors(n, seed);
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  const double spacing = std::sqrt(4 * kPi / n);
  Eigen::MatrixX3d out(n, 3);
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n;
    const double r = std::sqrt(1.0 - z * z);
    const Eigen::Vector3d p(r * std::cos(golden * i), r * std::sin(golden * i),
                            z);
    out.row(i) = (p + jitter * spacing * noise.row(i).transpose())
                     .normalized()
                     .transpose();
  }
  return out;
}

// `n` random unit vectors within angle `radius` (radians) of unit `center`.
inline Eigen::MatrixX3d RandomUnitVectorsInCap(int n,
                                               const Eigen::Vector3d& center,
                                               double radius, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::MatrixX3d out(n, 3);
  int i = 0;
  while (i < n) {
    const Eigen::Vector3d q =
        Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng)).normalized();
    if (q.dot(center) >= std::cos(radius)) out.row(i++) = q.transpose();
  }
  return out;
}

// Whether the unit vector p lies strictly inside the cone of the rows of
// `knots` (all in an open hemisphere): by Caratheodory's theorem for cones,
// iff it is inside the cone of some three of them (a plain floating-point
// barycentric test, independent of the library's predicates).
inline bool InsideSphericalHull(const Eigen::Vector3d& p,
                                const Eigen::MatrixX3d& knots) {
  const int m = static_cast<int>(knots.rows());
  for (int a = 0; a < m; ++a)
    for (int b = a + 1; b < m; ++b)
      for (int c = b + 1; c < m; ++c) {
        Eigen::Matrix3d t;
        t << knots.row(a).transpose(), knots.row(b).transpose(),
            knots.row(c).transpose();
        const Eigen::Vector3d x = t.fullPivLu().solve(p);
        if ((x.array() > 0).all()) return true;
      }
  return false;
}

}  // namespace testing
}  // namespace sdcb

#endif  // SDCB_TESTS_TESTING_RANDOM_SPHERE_POINTS_H_
