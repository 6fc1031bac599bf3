// Degree-k spherical Delaunay configurations (paper Sec. 2) and their
// grouping into unordered sets, one per DCB basis function.
//
// INTERFACE CONTRACT (implemented in delaunay_configurations.cpp):
// a configuration (X_B, X_I) has #X_B = 3, #X_I = k, and the smaller spherical
// cap of X_B contains exactly the knots X_I (decided with exact predicates,
// degeneracies resolved by a documented deterministic perturbation).
#ifndef SDCB_CORE_DELAUNAY_CONFIGURATIONS_H_
#define SDCB_CORE_DELAUNAY_CONFIGURATIONS_H_

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/status.h"

namespace sdcb {

// All configurations sharing one unordered knot set X~ = X_B u X_I: the
// support of one basis function.
struct ConfigurationSet {
  // The k + 3 knot indices of X~, ascending.
  std::vector<int> knots;
  // X_B of every configuration in <X>, each triple ascending, list sorted
  // lexicographically. X_I of each is `knots` minus the triple.
  std::vector<std::array<int, 3>> boundaries;
};

struct DelaunayConfigurations {
  int degree = 0;
  // Sorted lexicographically by `knots`; deterministic for given input.
  std::vector<ConfigurationSet> sets;
};

// Computes all degree-`degree` configurations of `knots` (#knots by 3, unit
// vectors on S^2), 0 <= degree <= 5, grouped by unordered set. Fails with
// kInvalidArgument for a bad degree, fewer than degree + 4 knots, non-unit
// or non-finite knots, or duplicate knots.
StatusOr<DelaunayConfigurations> ComputeDelaunayConfigurations(
    const Eigen::MatrixX3d& knots, int degree);

}  // namespace sdcb

#endif  // SDCB_CORE_DELAUNAY_CONFIGURATIONS_H_
