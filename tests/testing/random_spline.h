// Splines with random control points on given or random knots, for the
// evaluator tests (header-only).
#ifndef SDCB_TESTS_TESTING_RANDOM_SPLINE_H_
#define SDCB_TESTS_TESTING_RANDOM_SPLINE_H_

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <random>
#include <utility>

#include "sdcb/core/spline/delaunay_configurations.h"
#include "sdcb/core/spline/spherical_spline.h"
#include "testing/spline_model_fixture.h"

namespace sdcb::testing {

// A spline on the knots `k` whose control point i is the first knot of set
// i moved by a Gaussian of standard deviation `noise` per coordinate (near
// a unit sphere; with noise, folds included: any valid spline will do).
inline SphericalSpline SplineOnKnots(const Eigen::MatrixX3d& k, int degree,
                                     unsigned seed,
                                     BasisForm form = BasisForm::kNormalized,
                                     double noise = 0.2) {
  StatusOr<DelaunayConfigurations> c = ComputeDelaunayConfigurations(k, degree);
  EXPECT_TRUE(c.ok());
  StatusOr<DcbBasis> basis = DcbBasis::Create(k, *c);
  EXPECT_TRUE(basis.ok()) << basis.status().message();
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  Eigen::MatrixX3d cp(basis->size(), 3);
  for (int i = 0; i < basis->size(); ++i) {
    const Eigen::Vector3d dir = k.row(basis->configuration_set(i).knots[0]);
    cp.row(i) =
        (dir + noise * Eigen::Vector3d(g(rng), g(rng), g(rng))).transpose();
  }
  return std::move(SphericalSpline::Create(std::move(*basis), cp, form))
      .value();
}

// SplineOnKnots on `knots` random unit vectors (seed `seed`).
inline SphericalSpline RandomSpline(int degree, int knots, unsigned seed,
                                    BasisForm form = BasisForm::kNormalized,
                                    double noise = 0.2) {
  return SplineOnKnots(RandomUnitVectors(knots, seed), degree, seed, form,
                       noise);
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_RANDOM_SPLINE_H_
