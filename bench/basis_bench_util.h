// Quasi-uniform knots for the basis benchmarks: a Fibonacci spiral with a
// tiny deterministic jitter (general position), close to a uniform CVT.
#ifndef SDCB_BENCH_BASIS_BENCH_UTIL_H_
#define SDCB_BENCH_BASIS_BENCH_UTIL_H_

#include <Eigen/Core>
#include <cmath>
#include <random>

namespace sdcb {
namespace bench {

inline Eigen::MatrixX3d FibonacciKnots(int n, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  const double spacing = std::sqrt(4 * M_PI / n);
  Eigen::MatrixX3d out(n, 3);
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n;
    const double r = std::sqrt(1.0 - z * z);
    Eigen::Vector3d p(r * std::cos(golden * i), r * std::sin(golden * i), z);
    p +=
        0.05 * spacing * Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
    out.row(i) = p.normalized().transpose();
  }
  return out;
}

inline Eigen::MatrixX3d UniformPoints(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::MatrixX3d out(n, 3);
  for (int i = 0; i < n; ++i) {
    out.row(i) =
        Eigen::RowVector3d(normal(rng), normal(rng), normal(rng)).normalized();
  }
  return out;
}

}  // namespace bench
}  // namespace sdcb

#endif  // SDCB_BENCH_BASIS_BENCH_UTIL_H_
