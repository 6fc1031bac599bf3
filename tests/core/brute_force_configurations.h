// STAND-IN brute-force oracle for degree-k spherical Delaunay configurations:
// every triple, knots strictly inside its smaller cap counted with the exact
// CapSide predicate. O(n^4): keep n <= ~150. Same canonical order as
// DelaunayConfigurations (sets by `knots`, boundaries sorted).
#ifndef SDCB_TESTS_CORE_BRUTE_FORCE_CONFIGURATIONS_H_
#define SDCB_TESTS_CORE_BRUTE_FORCE_CONFIGURATIONS_H_

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <map>
#include <vector>

#include "core/delaunay_configurations.h"
#include "core/sphere_geometry.h"

namespace sdcb {
namespace testing {

inline DelaunayConfigurations BruteForceConfigurations(
    const Eigen::MatrixX3d& knots, int degree) {
  const int n = static_cast<int>(knots.rows());
  std::map<std::vector<int>, std::vector<std::array<int, 3>>> groups;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      for (int c = b + 1; c < n; ++c) {
        const Eigen::Vector3d ta = knots.row(a), tb = knots.row(b),
                              tc = knots.row(c);
        std::vector<int> set = {a, b, c};
        for (int q = 0; q < n && static_cast<int>(set.size()) <= degree + 3;
             ++q) {
          if (q == a || q == b || q == c) continue;
          if (CapSide(ta, tb, tc, knots.row(q).transpose()) > 0)
            set.push_back(q);
        }
        if (static_cast<int>(set.size()) != degree + 3) continue;
        std::sort(set.begin(), set.end());
        groups[set].push_back({a, b, c});
      }
  DelaunayConfigurations out;
  out.degree = degree;
  for (auto& [set, boundaries] : groups) {
    std::sort(boundaries.begin(), boundaries.end());
    out.sets.push_back(ConfigurationSet{set, boundaries});
  }
  return out;
}

}  // namespace testing
}  // namespace sdcb

#endif  // SDCB_TESTS_CORE_BRUTE_FORCE_CONFIGURATIONS_H_
