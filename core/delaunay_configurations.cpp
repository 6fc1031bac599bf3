// STAND-IN implementation of ComputeDelaunayConfigurations, written only so
// the basis code can be tested before the real (exact, fast) implementation
// lands; the lead drops this file at merge.
//
// Method: a triple {a, b, c} is a configuration when the smaller cap of the
// plane through it contains exactly `degree` knots (CapSide, exact). Small
// inputs test every triple. Larger ones only test triples whose other two
// knots are among the K nearest neighbours of one of its knots, and count
// the knots inside a cap exactly over the neighbourhood when the cap lies
// inside it (else over all knots). Completeness is then checked with the
// j-facet count 2(k+1)(n-k-2) for points in convex position; on a mismatch
// K doubles, up to n - 1. No perturbation: knots must be in general position.
#include "core/delaunay_configurations.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "core/sphere_geometry.h"

namespace sdcb {
namespace {

using Triple = std::array<int, 3>;

Eigen::Vector3d Row(const Eigen::MatrixX3d& m, int i) {
  return m.row(i).transpose();
}

// Number of knots (from `candidates`) strictly inside the cap of (a,b,c),
// appended to `inside`; stops early above `limit`. -1 if a knot lies on the
// circle.
int CountInside(const Eigen::MatrixX3d& knots, const Triple& t,
                const std::vector<int>& candidates, int limit,
                std::vector<int>* inside) {
  inside->clear();
  const Eigen::Vector3d a = Row(knots, t[0]), b = Row(knots, t[1]),
                        c = Row(knots, t[2]);
  int count = 0;
  for (int q : candidates) {
    if (q == t[0] || q == t[1] || q == t[2]) continue;
    const int side = CapSide(a, b, c, Row(knots, q));
    if (side == 0) return -1;
    if (side > 0) {
      inside->push_back(q);
      if (++count > limit) return count;
    }
  }
  return count;
}

// Floating-point pre-filter: true if more than `limit` knots are inside the
// cap by a margin far above rounding error (so the exact count exceeds it).
bool ClearlyMoreInside(const Eigen::MatrixX3d& knots, const Triple& t,
                       const std::vector<int>& candidates, int limit) {
  const Eigen::Vector3d a = Row(knots, t[0]);
  Eigen::Vector3d normal = (Row(knots, t[1]) - a).cross(Row(knots, t[2]) - a);
  double offset = normal.dot(a);
  if (offset < 0) {
    normal = -normal;
    offset = -offset;
  }
  const double margin = 1e-9 * normal.norm();
  int count = 0;
  for (int q : candidates) {
    if (normal.dot(Row(knots, q)) > offset + margin && ++count > limit) {
      return true;
    }
  }
  return false;
}

// `found` holds (X_B, X~) pairs, possibly repeated.
DelaunayConfigurations Group(
    int degree, std::vector<std::pair<Triple, std::vector<int>>> found) {
  std::sort(found.begin(), found.end());
  found.erase(std::unique(found.begin(), found.end()), found.end());
  std::map<std::vector<int>, std::vector<Triple>> groups;
  for (const auto& [t, set] : found) groups[set].push_back(t);
  DelaunayConfigurations out;
  out.degree = degree;
  for (auto& [set, boundaries] : groups) {
    out.sets.push_back(ConfigurationSet{set, boundaries});
  }
  return out;
}

}  // namespace

StatusOr<DelaunayConfigurations> ComputeDelaunayConfigurations(
    const Eigen::MatrixX3d& knots, int degree) {
  const int n = static_cast<int>(knots.rows());
  if (degree < 0 || degree > 5) {
    return InvalidArgumentError("degree must be in 0..5");
  }
  if (n < degree + 4) {
    return InvalidArgumentError("too few knots for the degree");
  }
  for (int i = 0; i < n; ++i) {
    if (!knots.row(i).allFinite() ||
        std::abs(knots.row(i).norm() - 1.0) > 1e-9) {
      return InvalidArgumentError("knot " + std::to_string(i) +
                                  " is not a finite unit vector");
    }
  }
  std::vector<int> all(n);
  for (int i = 0; i < n; ++i) all[i] = i;
  std::vector<std::pair<Triple, std::vector<int>>> found;
  std::vector<int> inside;
  auto record = [&](const Triple& t) {
    std::vector<int> set(t.begin(), t.end());
    set.insert(set.end(), inside.begin(), inside.end());
    std::sort(set.begin(), set.end());
    found.push_back({t, set});
  };
  const size_t expected =
      2 * static_cast<size_t>(degree + 1) * (n - degree - 2);
  if (n <= 60) {
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b)
        for (int c = b + 1; c < n; ++c) {
          if (CountInside(knots, {a, b, c}, all, degree, &inside) == degree)
            record({a, b, c});
        }
    return Group(degree, std::move(found));
  }
  // Neighbourhoods grow until the j-facet count is reached.
  for (int neighbours = std::min(n - 1, 30 + 6 * degree);;
       neighbours = std::min(n - 1, 2 * neighbours)) {
    found.clear();
    for (int a = 0; a < n; ++a) {
      std::vector<std::pair<double, int>> by_distance;
      for (int q = 0; q < n; ++q) {
        if (q != a) {
          by_distance.push_back(
              {(knots.row(q) - knots.row(a)).squaredNorm(), q});
        }
      }
      std::partial_sort(by_distance.begin(), by_distance.begin() + neighbours,
                        by_distance.end());
      std::vector<int> near = {a};
      for (int i = 0; i < neighbours; ++i)
        near.push_back(by_distance[i].second);
      const double reach = std::sqrt(by_distance[neighbours - 1].first);
      for (int i = 1; i <= neighbours; ++i)
        for (int j = i + 1; j <= neighbours; ++j) {
          Triple t = {a, near[i], near[j]};
          std::sort(t.begin(), t.end());
          if (ClearlyMoreInside(knots, t, near, degree)) continue;
          int count = CountInside(knots, t, near, degree, &inside);
          if (count < 0 || count > degree) continue;
          // The cap's chord diameter bounds the distance from a to any knot
          // inside it; if it exceeds the neighbourhood, count over all.
          const Eigen::Vector3d pa = Row(knots, t[0]), pb = Row(knots, t[1]),
                                pc = Row(knots, t[2]);
          const Eigen::Vector3d normal = (pb - pa).cross(pc - pa).normalized();
          const double h = std::abs(normal.dot(pa));
          const double diameter = 2.0 * std::sqrt(std::max(0.0, 1.0 - h * h));
          if (diameter >= reach) {
            count = CountInside(knots, t, all, degree, &inside);
          }
          if (count == degree) record(t);
        }
    }
    DelaunayConfigurations out = Group(degree, std::move(found));
    size_t total = 0;
    for (const ConfigurationSet& s : out.sets) total += s.boundaries.size();
    if (total == expected) return out;
    if (neighbours == n - 1) {
      return InternalError("stand-in configuration search: found " +
                           std::to_string(total) + " of " +
                           std::to_string(expected) +
                           " configurations (knots not spread or degenerate)");
    }
  }
}

}  // namespace sdcb
