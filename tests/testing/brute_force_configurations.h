// Brute-force oracle for spherical Delaunay configurations: every triple of
// knots, every other knot tested against its cap. O(n^4) worst case (with an
// early exit once a cap holds too many knots); for n <= ~200.
// Ties are decided by the same documented perturbation as the library
// (PerturbedCap), so it is the oracle for degenerate knot sets too.
#ifndef SDCB_TESTS_TESTING_BRUTE_FORCE_CONFIGURATIONS_H_
#define SDCB_TESTS_TESTING_BRUTE_FORCE_CONFIGURATIONS_H_

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <map>
#include <vector>

#include "sdcb/core/sphere/perturbed_predicates.h"
#include "sdcb/core/spline/delaunay_configurations.h"

namespace sdcb {
namespace testing {

// Configurations of every degree 0..max_degree; element j has degree j.
inline std::vector<DelaunayConfigurations> BruteForceConfigurationsUpTo(
    const Eigen::MatrixX3d& knots, int max_degree) {
  const int n = static_cast<int>(knots.rows());
  // Per degree: unordered set -> boundary triples (std::map keeps order).
  std::vector<std::map<std::vector<int>, std::vector<std::array<int, 3>>>>
      found(max_degree + 1);
  std::vector<int> inside;
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      for (int c = b + 1; c < n; ++c) {
        const PerturbedCap cap(knots, a, b, c);
        inside.clear();
        for (int q = 0; q < n; ++q) {
          if (q == a || q == b || q == c || !cap.Contains(q)) continue;
          inside.push_back(q);
          if (static_cast<int>(inside.size()) > max_degree) break;
        }
        const int degree = static_cast<int>(inside.size());
        if (degree > max_degree) continue;
        std::vector<int> all = inside;
        all.insert(all.end(), {a, b, c});
        std::sort(all.begin(), all.end());
        found[degree][all].push_back({a, b, c});  // a < b < c
      }
    }
  }
  std::vector<DelaunayConfigurations> result(max_degree + 1);
  for (int d = 0; d <= max_degree; ++d) {
    result[d].degree = d;
    for (auto& [set, boundaries] : found[d]) {
      std::sort(boundaries.begin(), boundaries.end());
      result[d].sets.push_back({set, boundaries});
    }
  }
  return result;
}

// Configurations of one degree, in the library's canonical order.
inline DelaunayConfigurations BruteForceConfigurations(
    const Eigen::MatrixX3d& knots, int degree) {
  return BruteForceConfigurationsUpTo(knots, degree)[degree];
}

}  // namespace testing
}  // namespace sdcb

#endif  // SDCB_TESTS_TESTING_BRUTE_FORCE_CONFIGURATIONS_H_
