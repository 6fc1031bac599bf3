// Range of the normalization I(p) = sum_i B_i(p) (paper eq. 5) over random
// points, for growing knot counts (issue 5): I > 0 everywhere and tends to 1
// as the knots densify. Usage: normalization_bench [degree=2] [points=20000]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "sdcb/core/spline/dcb_basis.h"
#include "sdcb/core/spline/delaunay_configurations.h"
#include "testing/random_sphere_points.h"

int main(int argc, char** argv) {
  const int degree = argc > 1 ? std::atoi(argv[1]) : 2;
  const int num_points = argc > 2 ? std::atoi(argv[2]) : 20000;
  const Eigen::MatrixX3d points =
      sdcb::testing::RandomUnitVectors(num_points, 17);
  std::printf("degree %d, I(p) over %d random points\n", degree, num_points);
  for (const char* kind : {"fibonacci", "random"}) {
    for (int n : {100, 120, 200, 500, 1000, 2000, 5000}) {
      const Eigen::MatrixX3d knots =
          std::string(kind) == "random"
              ? sdcb::testing::RandomUnitVectors(n, 23)
              : sdcb::testing::FibonacciPoints(n, 2);
      auto configurations = sdcb::ComputeDelaunayConfigurations(knots, degree);
      if (!configurations.ok()) {
        std::printf("%-9s n=%5d: %s\n", kind, n,
                    configurations.status().message().c_str());
        continue;
      }
      auto basis = sdcb::DcbBasis::Create(knots, *configurations);
      if (!basis.ok()) continue;
      double lo = 1e300, hi = 0.0;
      for (int r = 0; r < num_points; ++r) {
        const double i = basis->Normalization(points.row(r).transpose());
        lo = std::min(lo, i);
        hi = std::max(hi, i);
      }
      std::printf("%-9s n=%5d basis=%6d  min I=%.4f  max I=%.4f\n", kind, n,
                  basis->size(), lo, hi);
      std::fflush(stdout);
    }
  }
  return 0;
}
