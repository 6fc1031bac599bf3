// The sample lattices of the measurements: the points of a triangle or a
// square at level n, by integer coordinates, and the lattice's triangles.
// The one place they are generated: the fit's and compare's surface samples
// (a lattice in every knot triangle, core/measure/surface_deviation.h), the
// tessellator's verification (a lattice in every face,
// core/tessellate/face_verification.h) and the cage's deviation (a lattice in
// every cage face, converters/cage/cage_deviation.h) map the coordinates to
// their own weights or parameters.
#ifndef SDCB_CORE_MEASURE_SAMPLE_LATTICE_H_
#define SDCB_CORE_MEASURE_SAMPLE_LATTICE_H_

#include <Eigen/Core>
#include <vector>

namespace sdcb {

// Which way the lattice's triangles turn: counter-clockwise in the (i, j)
// plane, or in the (j, i) plane (the mirror image, for a caller whose first
// parameter is j, as the cage's (u, v) = (j / n, i / n)).
enum class LatticeOrientation { kIJ, kJI };

// The triangle lattice of level n >= 1: the points (i, j), i, j >= 0,
// i + j <= n (barycentric weights i / n, j / n of two corners and
// (n - i - j) / n of the third), and its n^2 triangles.
struct TriangleLattice {
  TriangleLattice(int level, LatticeOrientation orientation);

  // (n + 1)(n + 2) / 2.
  static int NumPoints(int level) { return (level + 1) * (level + 2) / 2; }
  // The row of (i, j) in `points`.
  int Index(int i, int j) const {
    return i * (level + 1) - i * (i - 1) / 2 + j;
  }

  int level;
  // Row-major over i: row i holds j = 0..n - i.
  std::vector<Eigen::Vector2i> points;
  // Rows of `points`. For each (i, j) with i + j < n, row-major: the upward
  // triangle of (i, j), (i + 1, j), (i, j + 1), then, if i + j < n - 1, the
  // downward one of (i + 1, j), (i + 1, j + 1), (i, j + 1). With kIJ in
  // that corner order; with kJI (counter-clockwise in (j, i)) upward
  // (i, j), (i, j + 1), (i + 1, j) and downward (i, j + 1), (i + 1, j + 1),
  // (i + 1, j).
  std::vector<Eigen::Vector3i> triangles;
  // Per triangle: 1 for an upward one. The upward triangles' edges are every
  // edge of the lattice once.
  std::vector<char> upward;
};

// The square lattice of level n >= 1: the points (i, j), 0 <= i, j <= n,
// row-major over i (row (i, j) at i * (n + 1) + j), and two triangles per
// cell, counter-clockwise in the (j, i) plane: (i, j), (i, j + 1),
// (i + 1, j + 1) and (i, j), (i + 1, j + 1), (i + 1, j).
struct SquareLattice {
  explicit SquareLattice(int level);

  // (n + 1)^2.
  static int NumPoints(int level) { return (level + 1) * (level + 1); }

  int level;
  std::vector<Eigen::Vector2i> points;
  std::vector<Eigen::Vector3i> triangles;
};

}  // namespace sdcb

#endif  // SDCB_CORE_MEASURE_SAMPLE_LATTICE_H_
