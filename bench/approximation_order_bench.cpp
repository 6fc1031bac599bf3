// Approximation order of the spherical DCB-spline (issue 5): least-squares
// fits of a smooth function on S^2 with quasi-uniform (Fibonacci, CVT-like)
// knots; each step quadruples the knots, so the spacing halves and the max
// error should fall by about 2^(k+1). Prints the errors and measured orders.
// Usage: approximation_order_bench [min_degree=2] [max_degree=5] [n0=50]
//        [steps=3] [normalized=1]  (0: fit with the raw B_i of eq. 4)
#include <Eigen/SparseCholesky>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "sdcb/core/spline/dcb_basis.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/core/spline/design_matrix.h"
#include "testing/random_sphere_points.h"

namespace {

// A smooth, non-polynomial test function on S^2.
double TestFunction(const Eigen::Vector3d& p) {
  return std::exp(0.8 * p.x()) * std::sin(1.5 * p.y() + p.z());
}

Eigen::VectorXd Sample(const Eigen::MatrixX3d& points) {
  Eigen::VectorXd f(points.rows());
  for (Eigen::Index r = 0; r < points.rows(); ++r) {
    f[r] = TestFunction(points.row(r).transpose());
  }
  return f;
}

// Max error of the least-squares fit, or a negative value on failure.
double FitMaxError(int n, int degree, bool normalized, int* num_basis) {
  const Eigen::MatrixX3d knots = sdcb::testing::FibonacciPoints(n, 3);
  auto configurations = sdcb::ComputeDelaunayConfigurations(knots, degree);
  if (!configurations.ok()) {
    std::fprintf(stderr, "n=%d: %s\n", n,
                 configurations.status().message().c_str());
    return -1;
  }
  auto basis = sdcb::DcbBasis::Create(knots, *configurations);
  if (!basis.ok()) return -1;
  *num_basis = basis->size();
  // 12 quasi-uniform samples per basis function; normal equations with a
  // tiny ridge (1e-12 of the mean diagonal) against rank deficiency.
  const Eigen::MatrixX3d samples =
      sdcb::testing::FibonacciPoints(12 * basis->size(), 5);
  sdcb::DesignMatrixOptions options;
  options.normalized = normalized;
  const Eigen::SparseMatrix<double> a =
      sdcb::BuildDesignMatrix(*basis, samples, options);
  Eigen::SparseMatrix<double> normal = a.transpose() * a;
  const double ridge = 1e-12 * normal.diagonal().mean();
  for (int i = 0; i < normal.rows(); ++i) normal.coeffRef(i, i) += ridge;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
  if (solver.info() != Eigen::Success) return -1;
  const Eigen::VectorXd c = solver.solve(a.transpose() * Sample(samples));
  const Eigen::MatrixX3d test = sdcb::testing::RandomUnitVectors(20000, 11);
  const sdcb::DesignMatrix at = sdcb::BuildDesignMatrix(*basis, test, options);
  return (at * c - Sample(test)).cwiseAbs().maxCoeff();
}

}  // namespace

int main(int argc, char** argv) {
  const int min_degree = argc > 1 ? std::atoi(argv[1]) : 2;
  const int max_degree = argc > 2 ? std::atoi(argv[2]) : 5;
  const int n0 = argc > 3 ? std::atoi(argv[3]) : 50;
  const int steps = argc > 4 ? std::atoi(argv[4]) : 3;
  const bool normalized = argc > 5 ? std::atoi(argv[5]) != 0 : true;
  std::printf("basis: %s\n",
              normalized ? "normalized Bbar = B / I (eq. 5)" : "raw B (eq. 4)");
  std::printf(
      "f = exp(0.8x) sin(1.5y + z); max error over 20000 random points\n");
  for (int k = min_degree; k <= max_degree; ++k) {
    double previous = -1;
    for (int s = 0, n = n0; s < steps; ++s, n *= 4) {
      int m = 0;
      const double e = FitMaxError(n, k, normalized, &m);
      if (previous > 0 && e > 0) {
        std::printf("k=%d n=%5d basis=%6d max_error=%.3e order=%.2f\n", k, n, m,
                    e, std::log2(previous / e));
      } else {
        std::printf("k=%d n=%5d basis=%6d max_error=%.3e\n", k, n, m, e);
      }
      std::fflush(stdout);
      previous = e;
    }
  }
  return 0;
}
