// Reproducible random knot sets for tests and benchmarks (header-only).
#ifndef SDCB_TESTS_TESTING_RANDOM_KNOTS_H_
#define SDCB_TESTS_TESTING_RANDOM_KNOTS_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "sdcb/core/common/constants.h"
#include "testing/random_sphere_points.h"

namespace sdcb {
namespace testing {

// n knots uniformly distributed on S^2 (normalized Gaussian vectors).
inline Eigen::MatrixX3d UniformKnots(int n, unsigned seed) {
  return RandomUnitVectors(n, seed);
}

// A point uniformly distributed in the cap of angular radius `radius_deg`
// around the unit vector `axis`.
inline Eigen::Vector3d PointInCap(const Eigen::Vector3d& axis,
                                  double radius_deg, std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double z =
      1.0 - uniform(*rng) * (1.0 - std::cos(radius_deg * kPi / 180));
  const double phi = 2 * kPi * uniform(*rng);
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  const Eigen::Vector3d u = axis.unitOrthogonal();
  const Eigen::Vector3d v = axis.cross(u);
  return (z * axis + r * std::cos(phi) * u + r * std::sin(phi) * v)
      .normalized();
}

// n knots, the first round(fraction * n) uniform in a cap of `radius_deg`
// around a fixed axis, the rest uniform on the sphere: the clusters that
// density-driven knot placement produces.
inline Eigen::MatrixX3d ClusteredKnots(int n, double fraction,
                                       double radius_deg, unsigned seed) {
  Eigen::MatrixX3d knots = UniformKnots(n, seed);
  std::mt19937 rng(seed + 1);
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  const int clustered = static_cast<int>(std::round(fraction * n));
  for (int i = 0; i < clustered; ++i) {
    knots.row(i) = PointInCap(axis, radius_deg, &rng);
  }
  return knots;
}

}  // namespace testing
}  // namespace sdcb

#endif  // SDCB_TESTS_TESTING_RANDOM_KNOTS_H_
