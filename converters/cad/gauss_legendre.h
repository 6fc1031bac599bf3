// Gauss-Legendre quadrature on [0, 1]: the nodes (increasing) and weights of
// order N, exact for polynomials of degree 2 N - 1 (the CAD faces' volume,
// area and least-squares rows).
#ifndef SDCB_CONVERTERS_CAD_GAUSS_LEGENDRE_H_
#define SDCB_CONVERTERS_CAD_GAUSS_LEGENDRE_H_

#include <array>
#include <cmath>

#include "sdcb/core/common/constants.h"

namespace sdcb {

// Newton on the Legendre polynomial from the usual cosine guesses.
template <int N>
struct GaussLegendre {
  std::array<double, N> x, w;
  GaussLegendre() {
    for (int i = 0; i < N; ++i) {
      double z = std::cos(kPi * (i + 0.75) / (N + 0.5)), derivative = 1.0;
      for (int iteration = 0; iteration < 100; ++iteration) {
        double p0 = 1.0, p1 = 0.0;
        for (int k = 1; k <= N; ++k) {
          const double p2 = p1;
          p1 = p0;
          p0 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p2) / k;
        }
        derivative = N * (z * p0 - p1) / (z * z - 1.0);
        const double step = p0 / derivative;
        z -= step;
        if (std::abs(step) < 1e-16) break;
      }
      x[i] = 0.5 * (1.0 - z);
      w[i] = 1.0 / ((1.0 - z * z) * derivative * derivative);
    }
  }
};

}  // namespace sdcb

#endif  // SDCB_CONVERTERS_CAD_GAUSS_LEGENDRE_H_
