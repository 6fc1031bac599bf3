#include "sdcb/core/mesh/icosphere.h"

#include <cassert>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace sdcb {

TriangleMesh MakeIcosphere(int subdivisions) {
  assert(subdivisions >= 0 && subdivisions <= 9);
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, t, 0},  {1, t, 0},   {-1, -t, 0},
                                    {1, -t, 0},  {0, -1, t},  {0, 1, t},
                                    {0, -1, -t}, {0, 1, -t},  {t, 0, -1},
                                    {t, 0, 1},   {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<Eigen::Vector3i> f = {
      {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
      {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
      {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
      {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const std::pair<int, int> key(std::min(a, b), std::max(a, b));
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      const int index = static_cast<int>(v.size()) - 1;
      midpoint.emplace(key, index);
      return index;
    };
    std::vector<Eigen::Vector3i> next;
    next.reserve(4 * f.size());
    for (const Eigen::Vector3i& tri : f) {
      const int ab = mid(tri[0], tri[1]), bc = mid(tri[1], tri[2]),
                ca = mid(tri[2], tri[0]);
      next.emplace_back(tri[0], ab, ca);
      next.emplace_back(tri[1], bc, ab);
      next.emplace_back(tri[2], ca, bc);
      next.emplace_back(ab, bc, ca);
    }
    f = std::move(next);
  }
  TriangleMesh mesh;
  mesh.vertices.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (size_t i = 0; i < v.size(); ++i) {
    mesh.vertices.row(static_cast<Eigen::Index>(i)) = v[i].transpose();
  }
  mesh.faces.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (size_t i = 0; i < f.size(); ++i) {
    mesh.faces.row(static_cast<Eigen::Index>(i)) = f[i].transpose();
  }
  return mesh;
}

}  // namespace sdcb
