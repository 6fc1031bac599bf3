#include "sdcb/core/measure/sample_lattice.h"

namespace sdcb {

TriangleLattice::TriangleLattice(int level, LatticeOrientation orientation)
    : level(level) {
  points.reserve(NumPoints(level));
  for (int i = 0; i <= level; ++i) {
    for (int j = 0; j <= level - i; ++j) points.emplace_back(i, j);
  }
  triangles.reserve(static_cast<size_t>(level) * level);
  upward.reserve(static_cast<size_t>(level) * level);
  const bool ij = orientation == LatticeOrientation::kIJ;
  for (int i = 0; i < level; ++i) {
    for (int j = 0; j < level - i; ++j) {
      const int a = Index(i, j), b = Index(i + 1, j), c = Index(i, j + 1);
      triangles.push_back(ij ? Eigen::Vector3i(a, b, c)
                             : Eigen::Vector3i(a, c, b));
      upward.push_back(1);
      if (j + 1 < level - i) {
        const int d = Index(i + 1, j + 1);
        triangles.push_back(ij ? Eigen::Vector3i(b, d, c)
                               : Eigen::Vector3i(c, d, b));
        upward.push_back(0);
      }
    }
  }
}

SquareLattice::SquareLattice(int level) : level(level) {
  points.reserve(NumPoints(level));
  for (int i = 0; i <= level; ++i) {
    for (int j = 0; j <= level; ++j) points.emplace_back(i, j);
  }
  const auto at = [level](int i, int j) { return i * (level + 1) + j; };
  triangles.reserve(2 * static_cast<size_t>(level) * level);
  for (int i = 0; i < level; ++i) {
    for (int j = 0; j < level; ++j) {
      triangles.emplace_back(at(i, j), at(i, j + 1), at(i + 1, j + 1));
      triangles.emplace_back(at(i, j), at(i + 1, j + 1), at(i + 1, j));
    }
  }
}

}  // namespace sdcb
