// Degree-k spherical Delaunay configurations (paper Sec. 2) and their
// grouping into unordered sets, one per DCB basis function.
//
// INTERFACE CONTRACT (implemented in delaunay_configurations.cpp):
// a configuration (X_B, X_I) has #X_B = 3, #X_I = k, and the smaller spherical
// cap of X_B contains exactly the knots X_I (decided with exact predicates,
// degeneracies resolved by a documented deterministic perturbation).
#ifndef SDCB_CORE_SPLINE_DELAUNAY_CONFIGURATIONS_H_
#define SDCB_CORE_SPLINE_DELAUNAY_CONFIGURATIONS_H_

#include <Eigen/Core>
#include <array>
#include <vector>

#include "sdcb/core/common/status.h"

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
// (|norm - 1| > kUnitVectorTolerance) or non-finite knots, duplicate knots, or
// knots not in convex position (only possible with three or more knots within
// about 1e-8 of each other: rounding off the sphere then dominates their
// curvature), or more than 2,097,150 knots (indices are packed into 21 bits).
//
// "Inside a cap" is decided by PerturbedCapSide
// (core/sphere/perturbed_predicates.h), so co-circular knots, planes through
// the origin and near-duplicates give a valid, deterministic configuration set:
// the exact configuration set of the symbolically perturbed knots. Algorithm:
// docs/CONFIGURATIONS.md.
StatusOr<DelaunayConfigurations> ComputeDelaunayConfigurations(
    const Eigen::MatrixX3d& knots, int degree);

struct DelaunayConfigurationOptions {
  // Also check every facet against the hull neighbours of its knots (a
  // redundant local emptiness test, for testing). Slower; same result.
  bool always_verify = false;
};

struct DelaunayConfigurationStats {
  // facets_per_degree[j]: planes through three knots with exactly j knots on
  // one side (either side), j = 0..degree. The search computes all of them;
  // for knots in convex position it is 2(j+1)(n-j-2) (Welzl), whatever
  // their distribution.
  std::vector<int> facets_per_degree;
  // configurations_per_degree[j]: those whose j knots avoid the origin's
  // side, i.e. the degree-j configurations (X_B, X_I).
  std::vector<int> configurations_per_degree;
};

// As above, with options; `stats` may be null.
StatusOr<DelaunayConfigurations> ComputeDelaunayConfigurations(
    const Eigen::MatrixX3d& knots, int degree,
    const DelaunayConfigurationOptions& options,
    DelaunayConfigurationStats* stats = nullptr);

}  // namespace sdcb

#endif  // SDCB_CORE_SPLINE_DELAUNAY_CONFIGURATIONS_H_
